#include "core/noise_density.hpp"

#include <algorithm>

namespace headingd::core {

void BlockMeans::reset() {
  sum_.setZero();
  filled_s_ = 0.0;
  samples_ = 0;
  blocks_ = 0;
  mean_.setZero();
  m2_.setZero();
  index_weighted_.setZero();
  largest_squared_level_ = 0.0;
}

void BlockMeans::close_block() {
  const Vec3 block_mean = sum_ / samples_;
  index_weighted_ += static_cast<double>(blocks_) * block_mean;
  largest_squared_level_ = std::max(largest_squared_level_, block_mean.squaredNorm());
  ++blocks_;
  const Vec3 delta = block_mean - mean_;
  mean_ += delta / blocks_;
  m2_ += delta.cwiseProduct(block_mean - mean_);
  sum_.setZero();
  samples_ = 0;
  filled_s_ = 0.0;
}

double BlockMeans::index_spread() const {
  const double n = blocks_;
  return n * (n * n - 1.0) / 12.0;
}

Vec3 BlockMeans::trend_per_block() const {
  if (blocks_ < 3) return Vec3::Zero();
  const double mean_index = 0.5 * (blocks_ - 1.0);
  return (index_weighted_ - mean_index * static_cast<double>(blocks_) * mean_) / index_spread();
}

void NoiseDensity::add(const BlockMeans& blocks) {
  if (blocks.blocks() < 3) return;
  squares_ += blocks.squares() * blocks.block_s();
  dof_ += blocks.blocks() - 1.0;
}

Vec3 NoiseDensity::density_squared() const { return dof_ > 0.0 ? Vec3(squares_ / dof_) : Vec3::Zero(); }

}  // namespace headingd::core
