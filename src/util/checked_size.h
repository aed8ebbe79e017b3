#pragma once
// Overflow-checked size arithmetic for counts, strides and offsets that come from files (glTF
// accessors and buffer views, image sizes). Plain size_t arithmetic wraps: a hostile count near
// 2^64/3 times 3 components becomes a small allocation and the reads after it run past it.
// A CheckedSize remembers that an operation overflowed; the result then fits no limit.
#include <cstddef>
#include <limits>

namespace ts {

class CheckedSize {
 public:
  CheckedSize(size_t value) : value_(value) {}  // NOLINT: implicit, so sizes read naturally

  friend CheckedSize operator+(CheckedSize a, CheckedSize b) {
    CheckedSize r(0);
    r.overflow_ =
        a.overflow_ || b.overflow_ || __builtin_add_overflow(a.value_, b.value_, &r.value_);
    return r;
  }
  friend CheckedSize operator*(CheckedSize a, CheckedSize b) {
    CheckedSize r(0);
    r.overflow_ =
        a.overflow_ || b.overflow_ || __builtin_mul_overflow(a.value_, b.value_, &r.value_);
    return r;
  }

  bool overflowed() const { return overflow_; }
  // True when the exact (unwrapped) result is <= limit.
  bool fitsWithin(size_t limit) const { return !overflow_ && value_ <= limit; }
  // The value; only meaningful when !overflowed() (SIZE_MAX otherwise, which fits no limit).
  size_t value() const { return overflow_ ? std::numeric_limits<size_t>::max() : value_; }

 private:
  size_t value_;
  bool overflow_ = false;
};

}  // namespace ts
