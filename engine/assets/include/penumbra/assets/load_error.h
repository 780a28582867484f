// The one exception type every loader in penumbra::assets throws.
//
// Contract: what() reads "<file>: <reason>", e.g. "terrain/dem.pgm: truncated: 1200 of 277266
// sample bytes". Loaders never crash or return partial data on bad input: a missing, empty,
// truncated or garbage file, wrong dimensions, NaN/inf values, out-of-range indices or a cyclic
// node graph all end in a LoadError. Threading: a plain value type.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra::assets {

class LoadError : public std::runtime_error {
 public:
  LoadError(std::string file, std::string reason)
      : std::runtime_error(file + ": " + reason),
        file_(std::move(file)),
        reason_(std::move(reason)) {}

  const std::string& file() const { return file_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_;
  std::string reason_;
};

}  // namespace penumbra::assets
