#pragma once
// Exceptions are for misuse and bad configuration only; algorithmic outcomes are status values.
#include <stdexcept>
#include <string>

#include "marsyn/export.hpp"

namespace marsyn {

// A configuration value a plugin cannot accept. `field` is the parameter's name relative to the
// plugin's parameter block; the loader prefixes the config path and line.
class MARSYN_EXPORT ParamError : public std::invalid_argument {
 public:
  ParamError(std::string field, const std::string& what)
      : std::invalid_argument(what), field_(std::move(field)) {}
  const std::string& field() const noexcept { return field_; }

 private:
  std::string field_;
};

}  // namespace marsyn
