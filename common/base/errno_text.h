// errno values in words, for messages.
#pragma once

#include <string>

namespace igms {

// What strerror says of `errnum` ("No such file or directory"), from any thread: strerror may
// share one buffer between threads, this does not.
std::string ErrnoText(int errnum);

}  // namespace igms
