// Regions of interest and the encodings images and edge maps travel in.
//
//  - raw: the region's pixels, row by row, no padding (width * channels bytes a row; BGR
//    order for 3-channel images).
//  - png: the region as a PNG file (lossless; an edge map of 0/255 compresses many-fold).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "common/base/result.h"

namespace igms::wire {

enum class ImageEncoding { kRaw, kPng };

// A rectangle of pixels: columns x .. x+width-1, rows y .. y+height-1. All four zero means
// the whole image.
struct PixelRegion {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;

  bool whole() const { return x == 0 && y == 0 && width == 0 && height == 0; }
};

// The rectangle `region` names inside an image of `size`, or an error when it is empty,
// negative or reaches outside the image (a region is never silently clipped: the caller
// asked for pixels that do not exist).
Result<cv::Rect> ResolveRegion(const PixelRegion& region, cv::Size size);

// Encodes an 8-bit 1- or 3-channel image (any view, e.g. a region of a larger image).
std::string EncodeImage(const cv::Mat& image, ImageEncoding encoding);

// Decodes what EncodeImage made. For raw data the size and channels must be given; an
// empty Mat when the data does not match them or does not decode.
cv::Mat DecodeImage(const std::string& data, ImageEncoding encoding, int width, int height,
                    int channels);

}  // namespace igms::wire
