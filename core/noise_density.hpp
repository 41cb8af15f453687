#pragma once
// White-noise density N (dps/sqrt(Hz)) from block means: for white rate noise the mean of a
// block of length T_b has variance N^2 / T_b, however the chip's low-pass has coloured the
// individual samples. Accumulates per segment; pooled across accepted segments.
#include <cstdint>

#include "core/sample.hpp"

namespace headingd::core {

class BlockMeans {
 public:
  explicit BlockMeans(double block_s) : block_s_(block_s) {}

  void reset();
  void add(const Vec3& rate_dps, double dt_s) {  // inline: it runs on every sample
    sum_ += rate_dps;
    ++samples_;
    filled_s_ += dt_s;
    if (filled_s_ + 1e-9 >= block_s_) close_block();
  }
  // add() on each of `count` samples with their intervals, the sums held in registers.
  void add_run(const Sample* samples, const double* dts, std::size_t count) {
    Vec3 sum = sum_;
    double filled_s = filled_s_;
    std::uint32_t in_block = samples_;
    for (std::size_t i = 0; i < count; ++i) {
      sum += samples[i].rate_dps;
      ++in_block;
      filled_s += dts[i];
      if (filled_s + 1e-9 >= block_s_) [[unlikely]] {
        sum_ = sum, samples_ = in_block, filled_s_ = filled_s;
        close_block();
        sum = sum_, in_block = samples_, filled_s = filled_s_;
      }
    }
    sum_ = sum, samples_ = in_block, filled_s_ = filled_s;
  }
  std::uint32_t blocks() const { return blocks_; }
  // Sum of squared deviations of the block means from their mean, per axis.
  const Vec3& squares() const { return m2_; }
  double block_s() const { return block_s_; }
  // Least-squares slope of the block means against their index, per axis (dps per block); zero
  // below three blocks. Its variance is a block mean's variance over index_spread(), the sum of
  // (k - mean k)^2 over the blocks.
  Vec3 trend_per_block() const;
  double index_spread() const;
  // The largest squared norm of a block mean (dps^2): how far out the segment's level went.
  double largest_squared_level() const { return largest_squared_level_; }

 private:
  void close_block();

  double block_s_;
  Vec3 sum_ = Vec3::Zero();
  double filled_s_ = 0.0;
  std::uint32_t samples_ = 0;
  std::uint32_t blocks_ = 0;
  Vec3 mean_ = Vec3::Zero();
  Vec3 m2_ = Vec3::Zero();
  Vec3 index_weighted_ = Vec3::Zero();  // sum over blocks of k * block mean, k from 0
  double largest_squared_level_ = 0.0;
};

class NoiseDensity {
 public:
  // Adds one still segment's block statistics (needs at least three blocks).
  void add(const BlockMeans& blocks);
  bool known() const { return dof_ > 0.0; }
  // N^2 per axis, dps^2/Hz (= dps^2 s).
  Vec3 density_squared() const;
  double degrees_of_freedom() const { return dof_; }

 private:
  Vec3 squares_ = Vec3::Zero();  // sum over segments of block-mean squares times block length
  double dof_ = 0.0;
};

}  // namespace headingd::core
