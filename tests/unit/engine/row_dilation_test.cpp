// The row dilation plane validation grows support images with must give exactly what cv::dilate
// gives: on random masks of several densities and shapes, with the disks validation uses, at the
// image's borders, and for elements it cannot take (handed to cv::dilate).

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <random>

#include "../../../core/src/segmentation/row_dilation.h"

namespace clearway::detail {
namespace {

cv::Mat randomMask(int rows, int columns, double density, std::mt19937& random) {
  std::bernoulli_distribution set(density);
  cv::Mat mask(rows, columns, CV_8UC1);
  for (int row = 0; row < rows; ++row)
    for (int column = 0; column < columns; ++column)
      mask.at<std::uint8_t>(row, column) = set(random) ? 255 : 0;
  return mask;
}

int differingPixels(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat difference;
  cv::compare(a, b, difference, cv::CMP_NE);
  return cv::countNonZero(difference);
}

TEST(RowDilation, MatchesOpenCvForDisksOnRandomMasks) {
  std::mt19937 random(7);
  int compared = 0;
  for (const int reach : {0, 1, 2, 5, 10, 13})
    for (const double density : {0.001, 0.02, 0.3})
      for (const cv::Size size : {cv::Size(1, 1), cv::Size(7, 40), cv::Size(63, 31)}) {
        const cv::Mat mask = randomMask(size.height, size.width, density, random);
        const cv::Mat disk =
            cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * reach + 1, 2 * reach + 1));
        cv::Mat expected, ours;
        cv::dilate(mask, expected, disk);
        dilateByCentredRows(mask, ours, disk);
        ASSERT_EQ(ours.size(), expected.size());
        EXPECT_EQ(differingPixels(ours, expected), 0)
            << "reach " << reach << ", density " << density << ", " << size;
        ++compared;
      }
  EXPECT_EQ(compared, 54);
}

TEST(RowDilation, MatchesOpenCvForEllipsesAndInPlace) {
  std::mt19937 random(11);
  cv::Mat mask = randomMask(50, 70, 0.01, random);
  for (const cv::Size size : {cv::Size(9, 3), cv::Size(3, 11), cv::Size(15, 7)}) {
    const cv::Mat ellipse = cv::getStructuringElement(cv::MORPH_ELLIPSE, size);
    cv::Mat expected;
    cv::dilate(mask, expected, ellipse);
    cv::Mat in_place = mask.clone();
    dilateByCentredRows(in_place, in_place, ellipse);
    EXPECT_EQ(differingPixels(in_place, expected), 0) << size;
  }
}

TEST(RowDilation, OneSetPixelGrowsIntoTheElementClippedAtTheBorder) {
  cv::Mat mask(9, 9, CV_8UC1, cv::Scalar(0));
  mask.at<std::uint8_t>(0, 1) = 255;  // near a corner
  const cv::Mat disk = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(7, 7));
  cv::Mat ours;
  dilateByCentredRows(mask, ours, disk);
  // The element's lower half, shifted to (row 0, column 1) and clipped by the image.
  for (int row = 0; row < 9; ++row)
    for (int column = 0; column < 9; ++column) {
      const int dr = row - 0 + 3, dc = column - 1 + 3;
      const bool inside = dr >= 0 && dr < 7 && dc >= 0 && dc < 7 && disk.at<std::uint8_t>(dr, dc);
      EXPECT_EQ(ours.at<std::uint8_t>(row, column), inside ? 255 : 0) << row << ", " << column;
    }
}

TEST(RowDilation, ElementsWithOffCentreRowsAreLeftToOpenCv) {
  std::mt19937 random(3);
  const cv::Mat mask = randomMask(30, 30, 0.05, random);
  cv::Mat lopsided = cv::Mat::zeros(5, 5, CV_8UC1);
  lopsided.at<std::uint8_t>(2, 2) = 1;
  lopsided.at<std::uint8_t>(2, 3) = 1;  // a run to one side only
  lopsided.at<std::uint8_t>(0, 0) = 1;
  cv::Mat expected, ours;
  cv::dilate(mask, expected, lopsided);
  dilateByCentredRows(mask, ours, lopsided);
  EXPECT_EQ(differingPixels(ours, expected), 0);
  EXPECT_GT(cv::countNonZero(expected), cv::countNonZero(mask));
}

}  // namespace
}  // namespace clearway::detail
