// libFuzzer target: the untrusted inputs of hapi_surface. Record 0 is the
// bytes of a PLY file (parsePly, as a tool reading a saved surface does);
// records 1-5 are sensor_msgs/Image messages through toFloatImage as
// SurfaceNodelet converts them (every encoding, byte order, truncated
// buffers, NaN/inf), the first 32FC1 one fused as a depth frame into a small
// volume, the others projected onto its mesh as imaging frames (sizes that
// do not match, NaN pixels). Input: records (bounded_message.hpp).
#include "bounded_message.hpp"

#include "surface_conversions.hpp"

#include "hapi_surface/ply_io.hpp"
#include "hapi_surface/surface_mapper.hpp"

#include <ros/time.h>
#include <sensor_msgs/Image.h>

#include <algorithm>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ros::Time::init();
  return 0;
}

namespace {

// A pinhole camera of the image's size (90 degrees across its larger side).
hapi_surface::PinholeCamera cameraFor(const hapi_surface::FloatImage& im) {
  hapi_surface::PinholeCamera c;
  c.width = im.width;
  c.height = im.height;
  c.fx = c.fy = 0.5 * std::max(im.width, im.height);
  c.cx = 0.5 * im.width;
  c.cy = 0.5 * im.height;
  return c;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_surface;
  hapi_fuzz::Records records(data, size);
  const std::uint8_t* rec;
  std::size_t len;
  if (!records.next(&rec, &len)) return 0;
  Mesh ply;
  std::vector<Rgb8> colours;
  std::string why;
  parsePly(std::string(reinterpret_cast<const char*>(rec), len), &ply, &colours, &why);

  SurfaceSettings s;
  s.volume_size_x = s.volume_size_y = s.volume_size_z = 0.02;
  s.voxel_size = 0.001;
  s.truncation = 0.003;
  s.min_depth = 0.01;
  s.max_depth = 2.0;
  s.settle_time = 0;  // fused at once: the imaging projection needs a volume
  SurfaceMapper mapper(s);
  bool have_depth = false;
  for (int i = 0; i < 5 && records.next(&rec, &len); ++i) {
    sensor_msgs::Image image;
    if (!hapi_fuzz::deserialise<sensor_msgs::Image_>(rec, len, &image)) continue;
    FloatImage f;
    if (toFloatImage(ros_glue::rawView(image), &f) != SurfaceStatus::kOk) continue;
    if (!have_depth && image.encoding == "32FC1") {
      DepthFrame frame;
      frame.camera = cameraFor(f);
      frame.depth = std::move(f);
      FrameUse use;
      have_depth = mapper.addDepthFrame(image.header.stamp.toSec(), std::move(frame), Eigen::Isometry3d::Identity(),
                                        &use) == SurfaceStatus::kOk;
      continue;
    }
    // The imaging camera: the image's own size, or a fixed one (a mismatch).
    PinholeCamera cam = cameraFor(f);
    if (image.header.seq % 2 == 1) cam.width = 64;
    mapper.addImagingFrame(f, cam, Eigen::Isometry3d::Identity());
  }
  if (have_depth) {
    const Mesh& m = mapper.mesh();
    plyBytes(m, {});
  }
  return 0;
}
