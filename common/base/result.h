// "A value or an error message": what a function returns when it computes something and can
// fail for a reason a person must read (docs/architecture.md, error policy). Modelled on
// absl::StatusOr; C++20 has no std::expected.
//
//   igms::Result<Manifest> LoadManifest(const std::filesystem::path& path);
//   ...
//   if (!r.ok()) return igms::ErrorMessage{"line 3: unknown key 'foo'"};
//   auto manifest = LoadManifest(path);
//   if (!manifest.ok()) { std::cerr << manifest.error() << "\n"; return 1; }
//   Use(*manifest);
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <variant>

namespace igms {

// Why something failed, in words a person can act on (what is wrong and where). Not named
// Error: igms::Error is a wire message (igms/common.proto).
struct ErrorMessage {
  std::string message;
};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}
  Result(ErrorMessage error) : state_(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return state_.index() == 0; }

  // The value. Asking a failed result for it is a programmer error: it throws
  // std::logic_error carrying the result's message.
  T& value() & { return CheckedValue(*this); }
  const T& value() const& { return CheckedValue(*this); }
  T&& value() && { return std::move(CheckedValue(*this)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T&& operator*() && { return std::move(*this).value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  // Why it failed; empty when ok.
  const std::string& error() const {
    static const std::string kNone;
    return ok() ? kNone : std::get<1>(state_).message;
  }

 private:
  template <class Self>
  static auto& CheckedValue(Self& self) {
    if (!self.ok()) {
      throw std::logic_error("Result::value() of a failed result: " + self.error());
    }
    return std::get<0>(self.state_);
  }

  std::variant<T, ErrorMessage> state_;
};

// For checks in the `bool Check(std::string* why)` style (options, inputs): stores `why` when
// the caller asked for it and returns false, so a check reads
//   if (bad) return Fail(error, "what is wrong");
inline bool Fail(std::string* error, std::string why) {
  if (error) *error = std::move(why);
  return false;
}

}  // namespace igms
