#pragma once
// The estimator method as the DDS types carry it (idl/headingd.idl), both ways.
#include "core/method.hpp"
#include "headingd.h"

namespace headingd::app {

inline headingd::msg::Method to_wire(core::Method method) {
  switch (method) {
    case core::Method::A:
      return headingd::msg::Method::METHOD_A;
    case core::Method::B:
      return headingd::msg::Method::METHOD_B;
    case core::Method::C:
      return headingd::msg::Method::METHOD_C;
    case core::Method::Auto:
      break;
  }
  return headingd::msg::Method::METHOD_AUTO;
}

inline core::Method from_wire(headingd::msg::Method method) {
  switch (method) {
    case headingd::msg::Method::METHOD_A:
      return core::Method::A;
    case headingd::msg::Method::METHOD_B:
      return core::Method::B;
    case headingd::msg::Method::METHOD_C:
      return core::Method::C;
    case headingd::msg::Method::METHOD_AUTO:
      break;
  }
  return core::Method::Auto;
}

}  // namespace headingd::app
