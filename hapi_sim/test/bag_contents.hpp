// What a generated bag holds, read back by the bag writers' tests: each
// topic's type, message count and latching, and the messages of one topic.
#pragma once

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <map>
#include <string>
#include <vector>

namespace hapi_sim_test {

struct BagTopics {
  std::map<std::string, std::string> types;  // topic -> message type
  std::map<std::string, int> counts;         // topic -> messages
  std::map<std::string, bool> latched;       // topic -> written with a latching connection header
};

inline BagTopics readBagTopics(const std::string& path) {
  BagTopics d;
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  for (const rosbag::ConnectionInfo* c : view.getConnections()) {
    d.types[c->topic] = c->datatype;
    d.latched[c->topic] = c->header && c->header->count("latching") && c->header->at("latching") == "1";
  }
  for (const rosbag::MessageInstance& m : view) d.counts[m.getTopic()]++;
  return d;
}

// The messages of `topic`, in bag order (empty when the topic is absent).
template <class M>
std::vector<M> readMessages(const std::string& path, const std::string& topic) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  std::vector<M> out;
  for (const rosbag::MessageInstance& m : view) out.push_back(*m.instantiate<M>());
  return out;
}

}  // namespace hapi_sim_test
