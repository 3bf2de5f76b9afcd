#pragma once
/// Counting refusals: one counter per error code, for metrics, and a callback with each refusal
/// so the server can log its reason.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>

#include "ricochet/db/result.h"

namespace ricochet::db {

/// Called with every refusal after it is counted. Runs on the thread calling the rules (the DB
/// thread under DbWorker). Never given a password or a token.
using OnRefusal = std::function<void(const DbError&)>;

class Refusals {
 public:
  explicit Refusals(OnRefusal on_refusal = {}) : on_refusal_(std::move(on_refusal)) {}

  /// Counts and reports the error of a failed DbResult or DbStatus; passes the result on.
  template <class R>
  R operator()(R result) {
    if (!result.ok()) note(result.error());
    return result;
  }
  void note(const DbError& error) {
    ++counts_[static_cast<std::size_t>(error.code)];
    if (on_refusal_) on_refusal_(error);
  }
  std::uint64_t count(DbErrorCode code) const { return counts_[static_cast<std::size_t>(code)]; }

 private:
  OnRefusal on_refusal_;
  std::array<std::uint64_t, kDbErrorCodeCount> counts_{};
};

}  // namespace ricochet::db
