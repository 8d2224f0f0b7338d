#pragma once
// Dilation of a 0/255 mask by a structuring element whose rows are runs centred on its anchor
// column, such as the disks and ellipses of cv::getStructuringElement(cv::MORPH_ELLIPSE, ...):
// the same result as cv::dilate with its default border (nothing outside the image is set).
//
// cv::dilate takes a non-rectangular element point by point. Here each image row first gets its
// horizontal distance to the nearest set pixel, and a pixel is set when, for some row of the
// element, that distance in the matching image row is within the row's half-width: one
// comparison per pixel and element row, which the compiler vectorises. Plane validation dilates
// every large plane's support image by a disk of the growth gap (21 x 21 cells for a multi-beam
// frame), a twentieth of such a frame's pipeline with cv::dilate.

#include <opencv2/core/mat.hpp>

namespace clearway::detail {

// `out` = `mask` dilated by `element` (CV_8U, odd size, anchor in its middle). An element whose
// rows are not centred runs, or a mask too wide for 16-bit distances, is left to cv::dilate.
void dilateByCentredRows(const cv::Mat& mask, cv::Mat& out, const cv::Mat& element);

}  // namespace clearway::detail
