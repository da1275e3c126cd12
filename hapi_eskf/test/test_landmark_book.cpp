// The pool's eviction policy (landmark_book.hpp), on the book alone: least
// recently seen first, and with full_pool_keep_observations the often
// observed landmarks last, whatever their age.
#include "hapi_eskf/backend/landmark_book.hpp"
#include "hapi_eskf/settings.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace hapi_eskf {
namespace {

// A full pool of 6: slots 0-2 created at t = 0 and observed 10 times up to
// t = 1 (an old, well-observed region), slots 3-5 created and last seen at
// t = 2, 3, 4 (observed once).
LandmarkBook fullBook() {
  LandmarkBook book;
  for (int k = 0; k < 3; ++k) book.add(Vec3(k, 0, 1), {{0, 0, 0}}, 0.0);
  for (int k = 0; k < 3; ++k)
    for (int n = 0; n < 9; ++n) book.observe(k, 1.0, {{0, 0, 0}});
  for (int k = 3; k < 6; ++k) book.add(Vec3(k, 0, 1), {{0, 0, 0}}, k - 1.0);
  return book;
}

EskfSettings poolOfSix() {
  EskfSettings s;
  s.max_landmarks = 6;
  s.max_new_landmarks = 4;
  s.full_pool_add_fraction = 0.5;  // a full pool makes room for ceil(0.5 * 4) = 2
  return s;
}

TEST(LandmarkBook, FullPoolEvictsTheLeastRecentlySeen) {
  const LandmarkBook book = fullBook();
  const EskfSettings s = poolOfSix();
  const std::vector<char> none(6, 0);
  EXPECT_EQ(book.chooseRemovals(4, none, s), (std::vector<int>{0, 1}));
  // Landmarks of this frame's update are never evicted.
  std::vector<char> used(6, 0);
  used[0] = 1;
  EXPECT_EQ(book.chooseRemovals(4, used, s), (std::vector<int>{1, 2}));
  // Room for what fits is made, no more: one addition, one eviction.
  EXPECT_EQ(book.chooseRemovals(1, none, s), (std::vector<int>{0}));
}

TEST(LandmarkBook, KeepObservationsEvictsTheOftenSeenLast) {
  const LandmarkBook book = fullBook();
  EskfSettings s = poolOfSix();
  const std::vector<char> none(6, 0);
  s.full_pool_keep_observations = 10;  // slots 0-2 (10 observations) are kept
  EXPECT_EQ(book.chooseRemovals(4, none, s), (std::vector<int>{3, 4}));
  s.full_pool_keep_observations = 11;  // none qualifies: least recently seen again
  EXPECT_EQ(book.chooseRemovals(4, none, s), (std::vector<int>{0, 1}));
  // When only kept landmarks can go, they go, least recently seen first.
  s.full_pool_keep_observations = 10;
  std::vector<char> used(6, 0);
  used[3] = used[4] = used[5] = 1;
  EXPECT_EQ(book.chooseRemovals(4, used, s), (std::vector<int>{0, 1}));
}

TEST(LandmarkBook, KeepObservationsIsValidated) {
  EskfSettings s;
  s.full_pool_keep_observations = -1;
  EXPECT_FALSE(s.validate().empty());
}

}  // namespace
}  // namespace hapi_eskf
