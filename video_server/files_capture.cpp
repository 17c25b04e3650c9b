#include "video_server/files_capture.h"

#include <spdlog/spdlog.h>

#include <cctype>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "common/base/clock.h"

namespace igms::video {
namespace {

struct PairPaths {
  std::string left;
  std::string right;
};

class FilesCapture : public CaptureBackend {
 public:
  FilesCapture(std::vector<PairPaths> pairs, bool colour, StereoImages first)
      : pairs_(std::move(pairs)), colour_(colour) {
    // A single pair never changes: keep it decoded instead of decoding it on every grab.
    if (pairs_.size() == 1) cached_ = std::move(first);
  }

  CaptureResult Capture(const PoseStamp& pose) override {
    const int64_t now = UnixNs();
    StereoImages images;
    if (cached_) {
      // Copies, so a caller that keeps or edits the images never shares them with the cache.
      images.left = cached_->left.clone();
      images.right = cached_->right.clone();
    } else {
      const PairPaths& pair = pairs_[next_];
      next_ = (next_ + 1) % pairs_.size();
      std::string error;
      if (!Decode(pair, colour_, images, error)) return CaptureResult::Error(error);
    }
    images.left_capture_unix_ns = now;
    images.right_capture_unix_ns = now;
    images.pose = pose;
    return CaptureResult::Ok(std::move(images));
  }

  std::string Describe() const override {
    std::string text = "files: " + pairs_.front().left + " / " + pairs_.front().right;
    if (pairs_.size() > 1) text += " (" + std::to_string(pairs_.size()) + " pairs)";
    return text;
  }

  static bool Decode(const PairPaths& pair, bool colour, StereoImages& images, std::string& error) {
    const int flags = colour ? cv::IMREAD_COLOR : cv::IMREAD_GRAYSCALE;
    images.left = cv::imread(pair.left, flags);
    if (images.left.empty()) {
      error = "cannot read image " + pair.left + " (missing, unreadable or not an image)";
      return false;
    }
    images.right = cv::imread(pair.right, flags);
    if (images.right.empty()) {
      error = "cannot read image " + pair.right + " (missing, unreadable or not an image)";
      return false;
    }
    error = CheckStereoImages(images);
    if (!error.empty()) error = pair.left + " and " + pair.right + ": " + error;
    return error.empty();
  }

 private:
  std::vector<PairPaths> pairs_;
  bool colour_;
  size_t next_ = 0;
  std::optional<StereoImages> cached_;
};

bool IsRegularFile(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

}  // namespace

bool IsFilePattern(const std::string& path) { return path.find('%') != std::string::npos; }

std::optional<std::string> FormatFilePattern(const std::string& pattern, int index) {
  std::string out;
  int fields = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      out += '%';
      ++i;
      continue;
    }
    size_t j = i + 1;
    const bool zero_pad = j < pattern.size() && pattern[j] == '0';
    if (zero_pad) ++j;
    int width = 0;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) &&
           width < 100) {
      width = width * 10 + (pattern[j] - '0');
      ++j;
    }
    if (j >= pattern.size() || pattern[j] != 'd' || width >= 100) return std::nullopt;
    std::string digits = std::to_string(index);
    if (static_cast<int>(digits.size()) < width) {
      digits.insert(0, width - digits.size(), zero_pad ? '0' : ' ');
    }
    out += digits;
    ++fields;
    i = j;
  }
  if (fields != 1) return std::nullopt;
  return out;
}

bool FilesCaptureOptions::Check(std::string* error) const {
  if (left.empty() || right.empty()) {
    *error = "the files backend needs a left and a right path";
    return false;
  }
  if (IsFilePattern(left) != IsFilePattern(right)) {
    *error = "left and right must both be plain paths or both be numbered patterns";
    return false;
  }
  if (IsFilePattern(left)) {
    if (!FormatFilePattern(left, 0) || !FormatFilePattern(right, 0)) {
      *error = "a numbered pattern needs exactly one integer field such as %d or %02d: " + left +
               ", " + right;
      return false;
    }
    if (first < 0 || first > last) {
      *error = "the index range is empty or negative";
      return false;
    }
  }
  return true;
}

FilesOpenResult OpenFilesCapture(const FilesCaptureOptions& options) {
  FilesOpenResult result;
  if (std::string error; !options.Check(&error)) {
    result.error = error;
    return result;
  }
  std::vector<PairPaths> pairs;
  if (!IsFilePattern(options.left)) {
    pairs.push_back({options.left, options.right});
  } else {
    for (int i = options.first; i <= options.last; ++i) {
      PairPaths pair{*FormatFilePattern(options.left, i), *FormatFilePattern(options.right, i)};
      const bool has_left = IsRegularFile(pair.left);
      const bool has_right = IsRegularFile(pair.right);
      if (has_left && has_right) {
        pairs.push_back(std::move(pair));
      } else if (has_left != has_right) {
        spdlog::warn("files backend: skipping index {}: {} has no partner {}", i,
                     has_left ? pair.left : pair.right, has_left ? pair.right : pair.left);
      }
    }
    if (pairs.empty()) {
      result.error = "no stereo pair matches " + options.left + " and " + options.right +
                     " for indices " + std::to_string(options.first) + ".." +
                     std::to_string(options.last);
      return result;
    }
  }
  StereoImages first;
  if (!FilesCapture::Decode(pairs.front(), options.colour, first, result.error)) return result;
  result.backend =
      std::make_unique<FilesCapture>(std::move(pairs), options.colour, std::move(first));
  return result;
}

}  // namespace igms::video
