// Internal: the C++ end of the progress callback of dualspectra::localize, called from Rust
// through the cxx bridge (rust/dualspectra-ffi/src/cxx_bridge.rs). Not part of the public API.
#pragma once

#include <exception>
#include <functional>
#include <string_view>

#include "rust/cxx.h"

namespace dualspectra {
namespace detail {

class ProgressSink {
 public:
  using Callback = std::function<bool(double fraction, std::string_view stage)>;

  explicit ProgressSink(Callback callback) : callback_(std::move(callback)) {}

  // Calls the callback; never throws. An exception thrown by the callback is stored (see
  // rethrow_if_failed) and cancels the computation. Calls are serialized by the Rust side.
  bool report(double fraction, rust::Str stage) const noexcept;
  bool is_active() const noexcept { return static_cast<bool>(callback_); }
  // Rethrows the callback's exception, if any.
  void rethrow_if_failed() const;

 private:
  Callback callback_;
  mutable std::exception_ptr error_;
};

}  // namespace detail
}  // namespace dualspectra
