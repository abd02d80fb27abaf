// Mesa's software rasterizer may compute with NaN internally (clipping, JIT-compiled
// shaders). Test binaries trap FE_INVALID to catch NaNs in our own code, so GL work runs
// with floating-point traps masked; threads llvmpipe starts inherit the masked state.
#pragma once

#include <cfenv>

namespace plastivox::render {

class FpTrapsMasked {
 public:
  FpTrapsMasked() : saved_(fegetexcept()) {
    if (saved_) fedisableexcept(saved_);
  }
  ~FpTrapsMasked() {
    if (saved_) {
      feclearexcept(FE_ALL_EXCEPT);
      feenableexcept(saved_);
    }
  }
  FpTrapsMasked(const FpTrapsMasked&) = delete;
  FpTrapsMasked& operator=(const FpTrapsMasked&) = delete;

 private:
  int saved_;
};

}  // namespace plastivox::render
