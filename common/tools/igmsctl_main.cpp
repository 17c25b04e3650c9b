#include "common/tools/igmsctl.h"

int main(int argc, char** argv) { return igms::tools::IgmsctlMain(argc, argv); }
