// The `files` capture backend: stereo pairs read from image files.
//
// Either one pair (left and right are plain paths: every capture returns that pair), or a
// numbered sequence (left and right are patterns with one integer field, printf style: "%d"
// or "%02d"; e.g. "data/left%02d.jpg" and "data/right%02d.jpg"). The sequence holds every
// index in [first, last] for which both files exist (gaps are skipped, as pair 10 of
// OpenCV's chessboard set); captures walk it in order and start again after the last pair.
// Any format cv::imread reads (PNG, JPEG, PGM, ...). Images are decoded to grey unless
// `colour` is set. Captures are stamped with the time decoding started and the pose given.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "video_server/capture_backend.h"

namespace igms::video {

struct FilesCaptureOptions {
  std::string left;
  std::string right;
  // Index range searched when left and right are patterns.
  int first = 0;
  int last = 9999;
  // Decode as 3-channel BGR instead of 8-bit grey.
  bool colour = false;

  // False, with what is wrong in *error, when unusable (empty path, bad pattern, first > last).
  bool Check(std::string* error) const;
};

struct FilesOpenResult {
  std::unique_ptr<CaptureBackend> backend;
  std::string error;
};

// Finds the pairs and decodes the first one to check it (readable, both sides the same size
// and type). Errors name the file at fault.
FilesOpenResult OpenFilesCapture(const FilesCaptureOptions& options);

// Formats a pattern with one printf integer field ("%d", "%02d", "%5d"; "%%" is a literal
// percent sign) for `index`. Returns nullopt when the pattern has no field, several, or
// another conversion. A string without '%' is not a pattern (IsFilePattern false).
std::optional<std::string> FormatFilePattern(const std::string& pattern, int index);
bool IsFilePattern(const std::string& path);

}  // namespace igms::video
