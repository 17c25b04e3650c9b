// igmsctl: the fake client. Sends any request of any IGMS service to a server and prints the
// response as protobuf JSON, or subscribes to any stream and prints or counts what arrives.
// It knows every service from the generated descriptors, so a new method needs no change
// here. Usage: igmsctl --help.
#pragma once

namespace igms::tools {

// The whole program, so tests can run it in-process as well as as a process.
int IgmsctlMain(int argc, char** argv);

}  // namespace igms::tools
