// rostest node of frontend_inputs.test: the front end's input variants end to
// end, on a synthetic textured stereo pair with a constant disparity DISP
// (every landmark at depth F*B/DISP):
//  - encodings mono8, mono16 (scaled to 8 bit: same landmarks as mono8),
//    bgr8 and rgb8 (same landmarks, colours in the right channel order);
//  - image_transport "compressed": PNG CompressedImage gives the mono8 result;
//  - raw distorted images with a rational_polynomial calibration: keypoints
//    are undistorted, the depth is right; the undistorted pair declared as
//    rectified (rectified_input true) ignores D and is right too.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <hapi_msgs/StereoLandmarks.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <cv_bridge/cv_bridge.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <random>

namespace {

constexpr int W = 640, H = 480, DISP = 16;
constexpr double F = 500.0, B = 0.1;
const double kDepth = F * B / DISP;  // 3.125 m
// A clearly visible rational_polynomial distortion (~7 % radial at the corners).
const std::vector<double> kRational = {-0.05, 0.01, 0.0005, -0.0003, 0.0, 0.05, 0.005, 0.0};

// "Dead leaves" texture (distinct corners, unlike a periodic pattern), W + DISP wide.
cv::Mat texture() {
  std::mt19937 rng(7);
  cv::Mat img(H, W + DISP, CV_8UC1, cv::Scalar(128));
  std::uniform_int_distribution<int> size(6, 59), grey(0, 255);
  for (int i = 0; i < 1500; ++i) {
    const int w = size(rng), h = size(rng);
    const int x = std::uniform_int_distribution<int>(0, W + DISP - w - 1)(rng);
    const int y = std::uniform_int_distribution<int>(0, H - h - 1)(rng);
    img(cv::Rect(x, y, w, h)).setTo(grey(rng));
  }
  cv::blur(img, img, cv::Size(3, 3));
  return img;
}

sensor_msgs::CameraInfo info(const ros::Time& t, bool right, const std::vector<double>& D, const std::string& model) {
  sensor_msgs::CameraInfo m;
  m.header.stamp = t;
  m.header.frame_id = right ? "in_right_optical_frame" : "in_left_optical_frame";
  m.width = W;
  m.height = H;
  m.distortion_model = model;
  m.D = D;
  m.K = {F, 0, W / 2.0, 0, F, H / 2.0, 0, 0, 1};
  m.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.P = {F, 0, W / 2.0, right ? -F * B : 0.0, 0, F, H / 2.0, 0, 0, 0, 1, 0};
  return m;
}

sensor_msgs::ImagePtr image(const ros::Time& t, const cv::Mat& px, const std::string& encoding, bool right) {
  std_msgs::Header h;
  h.stamp = t;
  h.frame_id = right ? "in_right_optical_frame" : "in_left_optical_frame";
  return cv_bridge::CvImage(h, encoding, px).toImageMsg();
}

// Distorted image of an ideal (undistorted) one: D(u_d) = I(undistort(u_d)).
cv::Mat distort(const cv::Mat& ideal, const std::vector<double>& D) {
  const cv::Matx33d K(F, 0, W / 2.0, 0, F, H / 2.0, 0, 0, 1);
  std::vector<cv::Point2f> px, und;
  px.reserve(W * H);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) px.emplace_back(u, v);
  cv::undistortPoints(px, und, K, D, cv::noArray(), K);
  cv::Mat mx(H, W, CV_32FC1), my(H, W, CV_32FC1);
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      mx.at<float>(v, u) = und[v * W + u].x;
      my.at<float>(v, u) = und[v * W + u].y;
    }
  cv::Mat out;
  cv::remap(ideal, out, mx, my, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

struct Output {
  std::mutex mu;
  std::vector<hapi_msgs::StereoLandmarks> msgs;
  void on(const hapi_msgs::StereoLandmarks::ConstPtr& m) {
    std::lock_guard<std::mutex> lk(mu);
    msgs.push_back(*m);
  }
  bool find(const ros::Time& t, hapi_msgs::StereoLandmarks* out) {
    std::lock_guard<std::mutex> lk(mu);
    for (const auto& m : msgs)
      if (m.header.stamp == t) {
        *out = m;
        return true;
      }
    return false;
  }
};

// One input set (prefix /enc, /cmp, ...) and the output of its instance.
struct Instance {
  ros::Publisher li, ri, lc, rc;  // images (raw or compressed), infos
  ros::Subscriber sub;
  Output out;
  Instance(ros::NodeHandle& nh, const std::string& prefix, const std::string& output, bool compressed) {
    if (compressed) {
      li = nh.advertise<sensor_msgs::CompressedImage>(prefix + "/left/image_raw/compressed", 5);
      ri = nh.advertise<sensor_msgs::CompressedImage>(prefix + "/right/image_raw/compressed", 5);
    } else {
      li = nh.advertise<sensor_msgs::Image>(prefix + "/left/image_raw", 5);
      ri = nh.advertise<sensor_msgs::Image>(prefix + "/right/image_raw", 5);
    }
    lc = nh.advertise<sensor_msgs::CameraInfo>(prefix + "/left/camera_info", 5);
    rc = nh.advertise<sensor_msgs::CameraInfo>(prefix + "/right/camera_info", 5);
    sub = nh.subscribe(output, 20, &Output::on, &out);
  }
  bool connected() const {
    return li.getNumSubscribers() > 0 && ri.getNumSubscribers() > 0 && lc.getNumSubscribers() > 0 &&
           rc.getNumSubscribers() > 0 && sub.getNumPublishers() > 0;
  }
  // Publishes one pair (messages already built) and waits for its output.
  template <typename Img>
  bool send(const ros::Time& t, const Img& l, const Img& r, const sensor_msgs::CameraInfo& linfo,
            const sensor_msgs::CameraInfo& rinfo, hapi_msgs::StereoLandmarks* result) {
    li.publish(l);
    lc.publish(linfo);
    ri.publish(r);
    rc.publish(rinfo);
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(30.0);
    while (ros::ok() && ros::WallTime::now() < end) {
      if (out.find(t, result)) return true;
      ros::WallDuration(0.01).sleep();
    }
    return false;
  }
};

template <typename P>
bool waitFor(P p, double s) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(s);
  while (ros::ok() && ros::WallTime::now() < end && !p()) ros::WallDuration(0.05).sleep();
  return p();
}

double medianDepthError(const hapi_msgs::StereoLandmarks& m) {
  std::vector<double> e;
  for (const auto& l : m.landmarks) e.push_back(std::abs(l.position.z - kDepth));
  if (e.empty()) return 1e9;
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  return e[e.size() / 2];
}

// Same landmarks (3D points and descriptors) in two outputs.
void expectSameLandmarks(const hapi_msgs::StereoLandmarks& a, const hapi_msgs::StereoLandmarks& b,
                         const std::string& what) {
  ASSERT_EQ(a.landmarks.size(), b.landmarks.size()) << what;
  for (std::size_t i = 0; i < a.landmarks.size(); ++i) {
    EXPECT_DOUBLE_EQ(a.landmarks[i].position.x, b.landmarks[i].position.x) << what << " #" << i;
    EXPECT_DOUBLE_EQ(a.landmarks[i].position.y, b.landmarks[i].position.y) << what << " #" << i;
    EXPECT_DOUBLE_EQ(a.landmarks[i].position.z, b.landmarks[i].position.z) << what << " #" << i;
  }
  EXPECT_EQ(a.descriptors, b.descriptors) << what;
}

std::mutex diag_mu;
std::map<std::string, std::map<std::string, std::string>> diag;  // status name -> values
void onDiag(const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
  std::lock_guard<std::mutex> lk(diag_mu);
  for (const auto& st : m->status)
    for (const auto& kv : st.values) diag[st.name][kv.key] = kv.value;
}
std::string diagValue(const std::string& node, const std::string& key) {
  std::lock_guard<std::mutex> lk(diag_mu);
  for (const auto& st : diag)
    if (st.first.rfind(node + ":", 0) == 0 && st.second.count(key)) return st.second.at(key);
  return "";
}

ros::NodeHandle* nh = nullptr;
cv::Mat left_ideal, right_ideal;  // mono8, rectified
ros::Time t_next;

ros::Time nextStamp() {
  t_next += ros::Duration(0.1);
  return t_next;
}

}  // namespace

TEST(FrontendInputs, EncodingsMono8Mono16Bgr8Rgb8) {
  Instance in(*nh, "/enc", "/stereo_frontend/landmarks", false);
  ASSERT_TRUE(waitFor([&] { return in.connected(); }, 30.0)) << "front end /enc never subscribed";
  const std::vector<double> D0(5, 0.0);
  std::map<std::string, hapi_msgs::StereoLandmarks> res;

  // mono8 and mono16 (v * 257: the full 16 bit range, which the front end
  // scales by 255 / 65535 back to exactly the mono8 image).
  for (const std::string enc : {"mono8", "mono16"}) {
    cv::Mat l = left_ideal, r = right_ideal;
    if (enc == "mono16") {
      left_ideal.convertTo(l, CV_16UC1, 257.0);
      right_ideal.convertTo(r, CV_16UC1, 257.0);
    }
    const ros::Time t = nextStamp();
    ASSERT_TRUE(in.send(t, image(t, l, enc, false), image(t, r, enc, true), info(t, false, D0, "plumb_bob"),
                        info(t, true, D0, "plumb_bob"), &res[enc]))
        << "no output for " << enc;
  }
  // Colour: R = G = grey, B = 255 - grey, in either channel order.
  auto colour = [](const cv::Mat& g, bool rgb) {
    cv::Mat inv = 255 - g, out;
    std::vector<cv::Mat> ch = rgb ? std::vector<cv::Mat>{g, g, inv} : std::vector<cv::Mat>{inv, g, g};
    cv::merge(ch, out);
    return out;
  };
  for (const std::string enc : {"bgr8", "rgb8"}) {
    const bool rgb = enc == "rgb8";
    const ros::Time t = nextStamp();
    ASSERT_TRUE(in.send(t, image(t, colour(left_ideal, rgb), enc, false), image(t, colour(right_ideal, rgb), enc, true),
                        info(t, false, D0, "plumb_bob"), info(t, true, D0, "plumb_bob"), &res[enc]))
        << "no output for " << enc;
  }
  for (const auto& kv : res) {
    std::printf("[frontend inputs] %s: %zu landmarks, median |z - %.3f| = %.4f m\n", kv.first.c_str(),
                kv.second.landmarks.size(), kDepth, medianDepthError(kv.second));
    EXPECT_GE(kv.second.landmarks.size(), 150u) << kv.first;
    EXPECT_LT(medianDepthError(kv.second), 0.01 * kDepth) << kv.first;
    EXPECT_EQ(kv.second.header.frame_id, "in_left_optical_frame");
  }
  expectSameLandmarks(res["mono8"], res["mono16"], "mono16 vs mono8");
  expectSameLandmarks(res["bgr8"], res["rgb8"], "rgb8 vs bgr8");
  // Colours in the message follow the image's channel order: r = g = grey, b = 255 - grey.
  for (const std::string enc : {"bgr8", "rgb8"}) {
    int ok = 0;
    for (const auto& l : res[enc].landmarks) ok += (l.r == l.g && std::abs(int(l.r) + int(l.b) - 255) <= 2);
    EXPECT_GE(ok, static_cast<int>(res[enc].landmarks.size() * 9 / 10)) << enc;
  }
  for (std::size_t i = 0; i < res["bgr8"].landmarks.size(); ++i) {
    EXPECT_EQ(res["bgr8"].landmarks[i].r, res["rgb8"].landmarks[i].r);
    EXPECT_EQ(res["bgr8"].landmarks[i].b, res["rgb8"].landmarks[i].b);
  }
}

TEST(FrontendInputs, CompressedTransportGivesTheRawResult) {
  Instance raw(*nh, "/enc", "/stereo_frontend/landmarks", false);
  Instance cmp(*nh, "/cmp", "/frontend_compressed/landmarks", true);
  ASSERT_TRUE(waitFor([&] { return raw.connected() && cmp.connected(); }, 30.0)) << "compressed front end never subscribed";
  const std::vector<double> D0(5, 0.0);
  auto png = [](const ros::Time& t, const cv::Mat& px, bool right) {
    sensor_msgs::CompressedImage m;
    m.header.stamp = t;
    m.header.frame_id = right ? "in_right_optical_frame" : "in_left_optical_frame";
    m.format = "mono8; png compressed mono8";
    cv::imencode(".png", px, m.data);
    return m;
  };
  hapi_msgs::StereoLandmarks from_raw, from_png;
  const ros::Time t = nextStamp();
  ASSERT_TRUE(raw.send(t, image(t, left_ideal, "mono8", false), image(t, right_ideal, "mono8", true),
                       info(t, false, D0, "plumb_bob"), info(t, true, D0, "plumb_bob"), &from_raw));
  ASSERT_TRUE(cmp.send(t, png(t, left_ideal, false), png(t, right_ideal, true), info(t, false, D0, "plumb_bob"),
                       info(t, true, D0, "plumb_bob"), &from_png))
      << "no output through the compressed transport";
  std::printf("[frontend inputs] compressed (PNG): %zu landmarks\n", from_png.landmarks.size());
  EXPECT_GE(from_png.landmarks.size(), 150u);
  expectSameLandmarks(from_raw, from_png, "PNG vs raw");
}

// Undecodable compressed data: no output for that pair, a counted rejection
// (the plugin hands over a 0x0 image), and the next good pair is processed.
TEST(FrontendInputs, UndecodableCompressedPairIsCountedNotFatal) {
  Instance cmp(*nh, "/cmp", "/frontend_compressed/landmarks", true);
  ASSERT_TRUE(waitFor([&] { return cmp.connected(); }, 30.0));
  const std::vector<double> D0(5, 0.0);
  sensor_msgs::CompressedImage junk;
  junk.format = "jpeg";
  junk.data.assign(1000, 0x5a);
  const ros::Time t = nextStamp();
  junk.header.stamp = t;
  sensor_msgs::CompressedImage junk_r = junk;
  junk_r.header.frame_id = "in_right_optical_frame";
  cmp.li.publish(junk);
  cmp.lc.publish(info(t, false, D0, "plumb_bob"));
  cmp.ri.publish(junk_r);
  cmp.rc.publish(info(t, true, D0, "plumb_bob"));
  ASSERT_TRUE(waitFor([] { return diagValue("frontend_compressed", "rejected.malformed_image") == "1"; }, 15.0))
      << "rejected.malformed_image = '" << diagValue("frontend_compressed", "rejected.malformed_image") << "'";
  hapi_msgs::StereoLandmarks none;
  EXPECT_FALSE(cmp.out.find(t, &none));
  // Still working.
  sensor_msgs::CompressedImage l, r;
  const ros::Time t2 = nextStamp();
  for (auto* m : {&l, &r}) {
    m->header.stamp = t2;
    m->format = "mono8; png compressed mono8";
  }
  r.header.frame_id = "in_right_optical_frame";
  cv::imencode(".png", left_ideal, l.data);
  cv::imencode(".png", right_ideal, r.data);
  hapi_msgs::StereoLandmarks ok;
  ASSERT_TRUE(cmp.send(t2, l, r, info(t2, false, D0, "plumb_bob"), info(t2, true, D0, "plumb_bob"), &ok));
  EXPECT_GE(ok.landmarks.size(), 150u);
}

TEST(FrontendInputs, RationalPolynomialRawAndRectifiedInput) {
  Instance dist(*nh, "/dist", "/frontend_distorted/landmarks", false);
  Instance rect(*nh, "/rect", "/frontend_rectified/landmarks", false);
  ASSERT_TRUE(waitFor([&] { return dist.connected() && rect.connected(); }, 30.0));
  const cv::Mat ld = distort(left_ideal, kRational), rd = distort(right_ideal, kRational);
  hapi_msgs::StereoLandmarks raw_out, rect_out;
  const ros::Time t = nextStamp();
  // Raw distorted images + rational_polynomial: keypoints undistorted and rectified.
  ASSERT_TRUE(dist.send(t, image(t, ld, "mono8", false), image(t, rd, "mono8", true),
                        info(t, false, kRational, "rational_polynomial"), info(t, true, kRational, "rational_polynomial"),
                        &raw_out));
  // The undistorted pair with the same CameraInfo declared rectified: D is ignored.
  ASSERT_TRUE(rect.send(t, image(t, left_ideal, "mono8", false), image(t, right_ideal, "mono8", true),
                        info(t, false, kRational, "rational_polynomial"), info(t, true, kRational, "rational_polynomial"),
                        &rect_out));
  std::printf("[frontend inputs] rational_polynomial raw: %zu landmarks, median depth error %.4f m; "
              "rectified_input: %zu, %.4f m\n", raw_out.landmarks.size(), medianDepthError(raw_out),
              rect_out.landmarks.size(), medianDepthError(rect_out));
  EXPECT_GE(raw_out.landmarks.size(), 150u);
  EXPECT_LT(medianDepthError(raw_out), 0.01 * kDepth);
  EXPECT_GE(rect_out.landmarks.size(), 150u);
  EXPECT_LT(medianDepthError(rect_out), 0.01 * kDepth);

  // Control: the same distorted images with the distortion left out of the
  // calibration give visibly wrong depths, so the check above can fail.
  hapi_msgs::StereoLandmarks ignored;
  const ros::Time t2 = nextStamp();
  const std::vector<double> D0(5, 0.0);
  ASSERT_TRUE(dist.send(t2, image(t2, ld, "mono8", false), image(t2, rd, "mono8", true),
                        info(t2, false, D0, "plumb_bob"), info(t2, true, D0, "plumb_bob"), &ignored));
  std::printf("[frontend inputs] control, distortion ignored: %zu landmarks, median depth error %.4f m\n",
              ignored.landmarks.size(), medianDepthError(ignored));
  EXPECT_GT(medianDepthError(ignored), 3.0 * medianDepthError(raw_out));
}

// gpu:=true without a device (or in a build without CUDA) falls back to the
// CPU path: same output as the CPU instance, "gpu used" False in /diagnostics.
// With a device the GPU path runs and must meet the same accuracy.
TEST(FrontendInputs, GpuRequestRunsOrFallsBackToCpu) {
  Instance cpu(*nh, "/enc", "/stereo_frontend/landmarks", false);
  Instance gpu(*nh, "/gpu", "/frontend_gpu/landmarks", false);
  ASSERT_TRUE(waitFor([&] { return cpu.connected() && gpu.connected(); }, 30.0));
  const std::vector<double> D0(5, 0.0);
  hapi_msgs::StereoLandmarks a, b;
  const ros::Time t = nextStamp();
  ASSERT_TRUE(cpu.send(t, image(t, left_ideal, "mono8", false), image(t, right_ideal, "mono8", true),
                       info(t, false, D0, "plumb_bob"), info(t, true, D0, "plumb_bob"), &a));
  ASSERT_TRUE(gpu.send(t, image(t, left_ideal, "mono8", false), image(t, right_ideal, "mono8", true),
                       info(t, false, D0, "plumb_bob"), info(t, true, D0, "plumb_bob"), &b));
  ASSERT_TRUE(waitFor([] { return !diagValue("frontend_gpu", "gpu used").empty() &&
                                  diagValue("frontend_gpu", "frames processed") != "0"; }, 15.0));
  const std::string used = diagValue("frontend_gpu", "gpu used");
  std::printf("[frontend inputs] gpu:=true -> gpu used: %s, %zu landmarks\n", used.c_str(), b.landmarks.size());
  EXPECT_GE(b.landmarks.size(), 150u);
  EXPECT_LT(medianDepthError(b), 0.01 * kDepth);
  if (used == "False" || used == "false" || used == "0") expectSameLandmarks(a, b, "CPU fallback vs CPU");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_frontend_inputs");
  ros::NodeHandle n;
  nh = &n;
  ros::Subscriber diag_sub = n.subscribe("/diagnostics", 50, onDiag);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  const cv::Mat tex = texture();
  left_ideal = tex(cv::Rect(0, 0, W, H)).clone();        // texture column X at left x = X
  right_ideal = tex(cv::Rect(DISP, 0, W, H)).clone();    // and at right x = X - DISP
  t_next = ros::Time::now();
  const int rc = RUN_ALL_TESTS();
  spinner.stop();
  return rc;
}
