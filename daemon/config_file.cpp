#include "daemon/config_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include <toml++/toml.h>

#include "core/method.hpp"

namespace headingd::app {
namespace {

std::string where(const std::string& file, const toml::node& node) {
  const auto& begin = node.source().begin;
  return file + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column);
}

[[noreturn]] void fail(const std::string& file, const toml::node& node, const std::string& key,
                       const std::string& problem) {
  throw ConfigError(where(file, node) + ": '" + key + "' " + problem);
}

std::string_view type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date/time";
  }
}

std::string shown(const toml::node& node) {
  std::ostringstream text;
  node.visit([&](const auto& value) { text << value; });
  return text.str();
}

double number_in(const std::string& file, const toml::node& node, const std::string& key, double lo,
                 double hi, bool lo_open) {
  std::optional<double> value;
  if (node.is_floating_point()) value = node.as_floating_point()->get();
  if (node.is_integer()) value = static_cast<double>(node.as_integer()->get());
  if (!value) fail(file, node, key, "must be a number, found " + std::string(type_name(node)) + " " + shown(node));
  const bool low_ok = lo_open ? *value > lo : *value >= lo;
  if (!std::isfinite(*value) || !low_ok || *value > hi) {
    std::ostringstream range;
    range << "is " << shown(node) << ", allowed " << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
    fail(file, node, key, range.str());
  }
  return *value;
}

void read_estimator(const std::string& file, const toml::table& table, core::BiasSettings& s) {
  for (const auto& [raw_key, node] : table) {
    const std::string key = "estimator." + std::string(raw_key.str());
    const std::string_view name = raw_key.str();
    if (name == "method") {
      const auto* text = node.as_string();
      const auto method = text ? core::parse_method(text->get()) : std::nullopt;
      if (!method) fail(file, node, key, "is " + shown(node) + ", allowed \"a\", \"b\" or \"c\"");
      s.method = *method;
    } else if (name == "segment_s") {
      s.segment_s = number_in(file, node, key, 0.0, 600.0, true);
    } else if (name == "k_range") {
      s.k_range = number_in(file, node, key, 0.0, 1000.0, true);
    } else if (name == "k_mean") {
      s.k_mean = number_in(file, node, key, 0.0, 1000.0, true);
    } else if (name == "n_means") {
      if (!node.is_integer()) fail(file, node, key, "must be an integer, found " + shown(node));
      s.n_means = static_cast<std::size_t>(number_in(file, node, key, 1.0, static_cast<double>(core::MeanHistory::kMaxMeans), false));
    } else if (name == "still_at_start") {
      if (!node.is_boolean()) fail(file, node, key, "must be true or false, found " + shown(node));
      s.still_at_start = node.as_boolean()->get();
    } else if (name == "sigma_still_dps") {
      const auto* array = node.as_array();
      if (array == nullptr || array->size() != 3)
        fail(file, node, key, "must be an array of three numbers [x, y, z] in dps, found " + shown(node));
      core::Vec3 sigma;
      for (std::size_t axis = 0; axis < 3; ++axis)
        sigma[static_cast<Eigen::Index>(axis)] = number_in(file, *array->get(axis), key, 0.0, 100.0, true);
      s.sigma_still_dps = sigma;
    } else {
      fail(file, node, key,
           "is not a known key (known: method, segment_s, k_range, k_mean, n_means, "
           "sigma_still_dps, still_at_start)");
    }
  }
}

Config interpret(const toml::table& root, const std::string& file) {
  Config config;
  for (const auto& [raw_key, node] : root) {
    const std::string key(raw_key.str());
    if (key == "estimator") {
      const auto* table = node.as_table();
      if (table == nullptr) fail(file, node, key, "must be a table ([estimator])");
      read_estimator(file, *table, config.estimator);
    } else {
      fail(file, node, key, "is not a known section (known: [estimator])");
    }
  }
  if (const auto problem = core::validate(config.estimator)) {
    throw ConfigError(file + ": [estimator]: " + *problem);
  }
  return config;
}

}  // namespace

Config parse_config(std::string_view text, const std::string& name) {
  try {
    const toml::table root = toml::parse(text, name);
    return interpret(root, name);
  } catch (const toml::parse_error& error) {
    const auto& begin = error.source().begin;
    throw ConfigError(name + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column) +
                      ": " + std::string(error.description()));
  }
}

Config load_config(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError("cannot open config " + path + ": " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_config(text.str(), path);
}

}  // namespace headingd::app
