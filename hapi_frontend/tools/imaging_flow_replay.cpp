// imaging_flow_replay: the image-flow measurement (ImageFlowTracker, as
// ImagingFlowNodelet runs it) on every imaging frame of a bag, written as
// text for the evaluation (docs/RUNNING.md "Image flow of the imaging camera").
//
//   imaging_flow_replay BAG OUT.txt [--topic T] [--u U] [--v V] [name=value ...]
//
// --topic: the imaging camera's image (default /imaging/image_raw); --u/--v:
// the pixel (default -1: the image centre); name=value: any ~ parameter of
// the nodelet by its ROS name (search_radius=60, mono16_bits=12), checked
// against its declared range. OUT.txt: '#' comment lines, then one line per
// imaging frame after the first, whitespace-separated:
//   t_prev t u v a0 a1 a2 a3 a4 a5 C00 .. C55 inliers tracked status
// t, t_prev [s]: the bag's image stamps (camera clock); a the affine flow
// [px/frame, 1/frame], C its covariance row-major, status as
// hapi_msgs/ImageFlow (0 ok, 1 too few features, 2 first frame after a
// restart: t_prev is then the frame before, which the flow does not connect
// to, and a, C are zero). Frames that cannot be used (bad encoding,
// truncated) are counted and written as no line.
#include "flow_message.hpp"
#include "imaging_flow_params.hpp"

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>

#include <cstdio>
#include <iostream>
#include <map>
#include <string>

namespace {

int usage(const std::string& why) {
  std::cerr << "imaging_flow_replay: " << why << "\n"
            << "usage: imaging_flow_replay BAG OUT.txt [--topic T] [--u U] [--v V] [name=value ...]\n";
  return 2;
}

// name=value on the tracker's settings, else on the nodelet's own.
std::string setParam(hapi_frontend::ImagingFlowNodeletParams* p, const std::string& name, const std::string& value) {
  const std::string flow_error = hapi_frontend::setFromText(&p->flow, name, value);
  if (flow_error.rfind("unknown parameter", 0) != 0) return flow_error;
  return hapi_frontend::setFromText(p, name, value);
}

void writeLine(std::FILE* out, const hapi_frontend::ImageFlowResult& r) {
  std::fprintf(out, "%.9f %.9f %.3f %.3f", r.previous_stamp_ns * 1e-9, r.stamp_ns * 1e-9, r.u, r.v);
  for (int i = 0; i < 6; ++i) std::fprintf(out, " %.9g", r.affine(i));
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) std::fprintf(out, " %.9g", r.covariance(i, j));
  std::fprintf(out, " %u %u %d\n", r.inliers, r.tracked, static_cast<int>(r.status));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage("need BAG and OUT.txt");
  std::string topic = "/imaging/image_raw";
  hapi_frontend::ImagingFlowNodeletParams params;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    const auto eq = a.find('=');
    std::string error;
    if (eq != std::string::npos) {
      error = setParam(&params, a.substr(0, eq), a.substr(eq + 1));
    } else {
      if (i + 1 >= argc) return usage("missing value after " + a);
      const std::string v = argv[++i];
      if (a == "--topic") topic = v;
      else if (a == "--u" || a == "--v") error = setParam(&params, a.substr(2), v);
      else return usage("unknown option " + a);
    }
    if (!error.empty()) return usage(error);
  }
  const std::string invalid = params.flow.validate();
  if (!invalid.empty()) return usage(invalid);
  try {
    rosbag::Bag bag(argv[1], rosbag::bagmode::Read);
    std::FILE* out = std::fopen(argv[2], "w");
    if (!out) return usage(std::string("cannot write ") + argv[2]);
    std::fprintf(out, "# imaging_flow_replay %s topic %s\n", argv[1], topic.c_str());
    std::fprintf(out, "# t_prev t u v a0 a1 a2 a3 a4 a5 C00..C55 inliers tracked status\n");
    hapi_frontend::ImageFlowTracker tracker(params.flow);
    int frames = 0, lines = 0, ok = 0;
    std::map<std::string, int> bad;
    rosbag::View view(bag, rosbag::TopicQuery(topic));
    for (const rosbag::MessageInstance& m : view) {
      const auto img = m.instantiate<sensor_msgs::Image>();
      if (!img) continue;
      ++frames;
      cv::Mat grey;
      hapi_frontend::ImageFlowResult r;
      hapi_frontend::InputError e = hapi_frontend::convertToGrey(hapi_frontend::rawView(*img), params.mono16_bits, &grey);
      if (!e) e = tracker.process(grey, static_cast<std::int64_t>(img->header.stamp.toNSec()), &r);
      if (e) ++bad[e.reason];
      if (e && e.reason != "size_changed") continue;
      if (r.status == hapi_frontend::FlowStatus::kFirstFrame && r.previous_stamp_ns == 0) continue;  // the first
      writeLine(out, r);
      ++lines;
      ok += r.status == hapi_frontend::FlowStatus::kOk;
    }
    std::fclose(out);
    std::printf("imaging_flow_replay: %d frames on %s, %d lines written to %s (%d with a valid flow)", frames,
                topic.c_str(), lines, argv[2], ok);
    for (const auto& kv : bad) std::printf(", %d %s", kv.second, kv.first.c_str());
    std::printf("\n");
    return lines > 0 ? 0 : 1;
  } catch (const std::exception& ex) {
    std::cerr << "imaging_flow_replay: " << ex.what() << "\n";
    return 1;
  }
}
