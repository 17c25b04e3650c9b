// An image of what the locator found, for a person to look at (`igms locate --debug-image`).
//
// Layout: on top the left and right images, each with the marks' quadrilateral (yellow, left
// only) and the fitted outline (magenta); below, the same two views enlarged around the
// object (up to 6x) with the strong edge pixels inside the marks (blue, left only), the edge
// points the final fit measured (green when they counted, red when rejected as outliers) and
// the fitted outline; a caption with the result or the failure's reason. Needs a result
// located with LocateInput::want_trace.
#pragma once

#include <opencv2/core.hpp>

#include "object_server/locate.h"

namespace igms::object {

// The picture as a BGR image; the input's images are those given to Locate.
cv::Mat DebugImage(const LocateInput& input, const LocateResult& result);

}  // namespace igms::object
