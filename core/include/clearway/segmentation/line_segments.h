#pragma once

// Stage 1 (paper II-A): straight segments in every scan line.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "clearway/progress.h"
#include "clearway/scan.h"
#include "clearway/segmentation/params.h"

namespace clearway {

// Running sums of a point set, enough to fit a least-squares plane or line to any union of sets.
struct PointMoments {
  double count = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();  // sum of p p^T

  void add(const Eigen::Vector3d& p) {
    count += 1.0;
    sum += p;
    outer += p * p.transpose();
  }
  PointMoments& operator+=(const PointMoments& other) {
    count += other.count;
    sum += other.sum;
    outer += other.outer;
    return *this;
  }
  Eigen::Vector3d mean() const { return sum / count; }
  Eigen::Matrix3d covariance() const { return outer / count - mean() * mean().transpose(); }
};

struct LineSegment {
  std::uint32_t line = 0;
  std::uint32_t first = 0;                          // index of the first point (Scan::points)
  std::uint32_t last = 0;                           // index of the last point, inclusive
  Eigen::Vector3f start = Eigen::Vector3f::Zero();  // fitted end points
  Eigen::Vector3f end = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();  // unit, start -> end
  float range = 0.0F;  // mean distance of its points from the sensor
  PointMoments moments;

  float length() const { return (end - start).norm(); }
};

// Segments of every line, ordered by line then position. Runs the lines on `threads` threads.
std::vector<LineSegment> detectLineSegments(const Scan& scan, const LineParams& params,
                                            int threads = 2, const ProgressCallback& progress = {});

}  // namespace clearway
