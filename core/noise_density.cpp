#include "core/noise_density.hpp"

namespace headingd::core {

void BlockMeans::reset() {
  sum_.setZero();
  filled_s_ = 0.0;
  samples_ = 0;
  blocks_ = 0;
  mean_.setZero();
  m2_.setZero();
}

void BlockMeans::close_block() {
  const Vec3 block_mean = sum_ / samples_;
  ++blocks_;
  const Vec3 delta = block_mean - mean_;
  mean_ += delta / blocks_;
  m2_ += delta.cwiseProduct(block_mean - mean_);
  sum_.setZero();
  samples_ = 0;
  filled_s_ = 0.0;
}

void NoiseDensity::add(const BlockMeans& blocks) {
  if (blocks.blocks() < 3) return;
  squares_ += blocks.squares() * blocks.block_s();
  dof_ += blocks.blocks() - 1.0;
}

Vec3 NoiseDensity::density_squared() const { return dof_ > 0.0 ? Vec3(squares_ / dof_) : Vec3::Zero(); }

}  // namespace headingd::core
