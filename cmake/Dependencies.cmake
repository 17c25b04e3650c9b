# Every find_package of the project, in one place. All come from Debian 12's packages
# (deploy/install-deps.sh installs them); nothing is vendored.
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(OpenCV 4 REQUIRED COMPONENTS core imgproc imgcodecs calib3d videoio highgui)
find_package(Boost 1.74 REQUIRED COMPONENTS program_options)
find_package(Protobuf REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(spdlog REQUIRED)
find_package(SQLite3 REQUIRED)
find_package(OpenSSL REQUIRED COMPONENTS Crypto SSL)  # SHA-256 of the calibration; TLS (docs/security.md)
find_package(glfw3 3.3 REQUIRED)
find_package(OpenGL REQUIRED COMPONENTS OpenGL EGL)  # EGL: offscreen rendering
find_package(OpenAL REQUIRED)
find_package(PkgConfig REQUIRED)
pkg_check_modules(SNDFILE REQUIRED IMPORTED_TARGET sndfile)
# Debian's pocketsphinx.pc names an include folder that does not exist, so IMPORTED_TARGET
# fails; the plain variables are used instead (see device_daemons/voice).
pkg_check_modules(POCKETSPHINX pocketsphinx)
if(IGMS_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(IGMS_BUILD_BENCH)
  find_package(benchmark QUIET)
endif()
# Fuzz targets need clang's libFuzzer; they are built in a separate clang build tree
# (deploy/lab fuzz), never by the default g++ build.
