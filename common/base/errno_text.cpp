#include "common/base/errno_text.h"

#include <cstring>

namespace igms {

std::string ErrnoText(int errnum) {
  char buffer[256];
  // The GNU strerror_r (the one C++ gets on glibc): it returns the text, which may be a static
  // string rather than `buffer`.
  return ::strerror_r(errnum, buffer, sizeof buffer);
}

}  // namespace igms
