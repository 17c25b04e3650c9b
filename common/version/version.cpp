#include "common/version/version.h"

#include <errno.h>  // program_invocation_short_name (glibc)

namespace igms::version {

namespace detail {
extern const char* const kRevision;  // revision.cpp, generated at build time
}  // namespace detail

std::string_view Project() { return IGMS_PROJECT_VERSION; }

std::string_view Revision() { return detail::kRevision; }

std::string Full() {
  std::string out(Project());
  std::string_view revision = Revision();
  if (revision.empty()) return out;
  // Semantic-versioning build metadata allows only [0-9A-Za-z-.]: "-dirty" becomes ".dirty".
  constexpr std::string_view kDirty = "-dirty";
  const bool dirty = revision.size() > kDirty.size() && revision.ends_with(kDirty);
  if (dirty) revision.remove_suffix(kDirty.size());
  out += "+g";
  out += revision;
  if (dirty) out += ".dirty";
  return out;
}

std::string ProgramName() { return program_invocation_short_name; }

std::string Line(std::string_view program) { return std::string(program) + " " + Full(); }

}  // namespace igms::version
