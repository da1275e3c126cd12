// libFuzzer target: sensor_msgs/Image sequences through the image-flow path
// as ImagingFlowNodelet::onImage runs it: roscpp deserialisation,
// convertToGrey (every encoding, byte order, truncated buffers, float maps
// with NaN/inf), ImageFlowTracker::process (stamps out of order, gaps, size
// changes, blank and tiny images) and the ImageFlow message. The tracker
// persists across the images of one input, as in the nodelet. Input: up to
// 6 records, each one image (bounded_message.hpp).
#include "bounded_message.hpp"

#include "flow_message.hpp"

#include "hapi_frontend/grey_convert.hpp"
#include "hapi_frontend/image_flow_tracker.hpp"

#include <hapi_msgs/ImageFlow.h>
#include <ros/time.h>
#include <sensor_msgs/Image.h>

#include <opencv2/core/utility.hpp>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ros::Time::init();
  cv::setNumThreads(0);  // one thread: reproducible, and no leak reports from a worker pool at exit
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hapi_frontend;
  ImageFlowParams params;
  params.search_radius = 24;  // the seeds' images are small
  ImageFlowTracker tracker(params);
  hapi_fuzz::Records records(data, size);
  for (int i = 0; i < 6; ++i) {
    const std::uint8_t* rec;
    std::size_t len;
    if (!records.next(&rec, &len)) break;
    sensor_msgs::Image image;
    if (!hapi_fuzz::deserialise<sensor_msgs::Image_>(rec, len, &image)) continue;
    cv::Mat grey;
    if (convertToGrey(rawView(image), 12, &grey)) continue;
    ImageFlowResult result;
    const InputError e = tracker.process(grey, static_cast<std::int64_t>(image.header.stamp.toNSec()), &result);
    if (e && e.reason != "size_changed") continue;
    hapi_msgs::ImageFlow msg;
    fillFlowMsg(result, image.header, &msg);
  }
  return 0;
}
