// The renderer's error: drawing, fonts, assets and image output. (Video and stats files have
// their own, with what throws them: VideoError in video_writer.hpp, StatsError in panels.hpp.)
#pragma once

#include "plastivox/base/error.hpp"

namespace plastivox::render {

// Any rendering failure (no GL context, missing font or asset, unwritable output);
// what() is one line naming the file or setting at fault.
class RenderError : public Error {
 public:
  using Error::Error;
};

}  // namespace plastivox::render
