// The matcher's two concurrent sweeps (rows exchanged through one cost volume) give
// exactly the single-threaded result, frame after frame; run under ThreadSanitizer
// too (world_test, stereo_threads_test).
#include <opencv2/core.hpp>

#include "specht/stereo/sgm.h"
#include "test_support.h"

namespace specht::stereo {
namespace {

TEST(SgmThreadsTest, TwoSweepThreadsMatchOneThreadOnEveryFrame) {
  cv::RNG rng(7);
  SgmOptions one, two;
  one.num_disparities = two.num_disparities = 64;
  one.threads = 1;
  two.threads = 2;
  SemiGlobalMatcher sequential(one), concurrent(two);
  for (int frame = 0; frame < 4; ++frame) {
    cv::Mat right(96, 160, CV_8UC1), left(96, 160, CV_8UC1, cv::Scalar(0));
    rng.fill(right, cv::RNG::UNIFORM, 0, 255);
    const int shift = 5 + 7 * frame;
    right(cv::Rect(0, 0, right.cols - shift, right.rows))
        .copyTo(left(cv::Rect(shift, 0, right.cols - shift, right.rows)));
    const cv::Mat a = sequential.Compute(left, right), b = concurrent.Compute(left, right);
    EXPECT_EQ(cv::countNonZero(a != b), 0) << "frame " << frame;
    EXPECT_GT(cv::countNonZero(b > 0), static_cast<int>(b.total() / 2));
  }
}

}  // namespace
}  // namespace specht::stereo
