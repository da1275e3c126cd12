// libFuzzer target: sensor_msgs/CompressedImage bytes through hapi_frontend's
// image_transport "compressed" plugin (decodeCompressed: OpenCV's JPEG/PNG
// decoders, the format string, the encoding choice), then the front end's
// conversion of the decoded image (toGrey), as the nodelet receives it.
// Input: one serialised CompressedImage (bounded_message.hpp).
#include "bounded_message.hpp"

#include "compressed_subscriber.hpp"
#include "image_input.hpp"

#include <ros/time.h>
#include <sensor_msgs/CompressedImage.h>

#include <boost/make_shared.hpp>
#include <opencv2/core/utility.hpp>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  ros::Time::init();
  cv::setNumThreads(0);
  // No decoder limit of the harness's own: decoding bombs (a few bytes of
  // header announcing a gigapixel image) meet the plugin's header check
  // (image_header.hpp) as they would on the robot.
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sensor_msgs::CompressedImage in;
  if (!hapi_fuzz::deserialise<sensor_msgs::CompressedImage_>(data, size, &in)) return 0;
  auto image = boost::make_shared<sensor_msgs::Image>();
  std::string error;
  hapi_frontend::decodeCompressed(in, image.get(), &error);
  hapi_frontend::GreyImage grey;
  hapi_frontend::toGrey(image, 16, &grey);
  return 0;
}
