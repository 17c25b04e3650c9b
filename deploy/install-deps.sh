#!/usr/bin/env bash
# Installs exactly the Debian 12 packages that IGMS needs to build, test and run its demo.
# Idempotent and quick when everything is present; uses sudo when not run as root.
#
#   deploy/install-deps.sh [--runtime] [--list]
#   --runtime  only what the installed programs need to run: shared libraries and data, no
#              compiler, no headers (the Dockerfile's run stage)
#   --list     print the packages, one a line, and install nothing
set -euo pipefail
RUNTIME=0
LIST=0
for arg in "$@"; do
  case "$arg" in
    --runtime) RUNTIME=1 ;;
    --list) LIST=1 ;;
    *) echo "install-deps: unknown option '$arg' (--runtime, --list)" >&2; exit 2 ;;
  esac
done

PACKAGES=(
  # toolchain
  cmake g++ make ninja-build pkg-config git
  # libraries the build links
  libeigen3-dev libopencv-dev libboost-dev libboost-system-dev libboost-program-options-dev
  libprotobuf-dev protobuf-compiler libyaml-cpp-dev libspdlog-dev
  libglfw3-dev libopenal-dev libsndfile1-dev libsqlite3-dev libssl-dev
  # the control client's window renders offscreen without a display: EGL through Mesa
  libegl-dev libegl-mesa0
  libpocketsphinx-dev pocketsphinx pocketsphinx-en-us sphinxtrain
  # real recorded speech (none of it a command): the recogniser's rejection test
  pocketsphinx-testdata
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev clang-14 libclang-rt-14-dev
  # the project's style and static checks (deploy/lab format, deploy/lab lint)
  clang-format-14 clang-tidy-14
  # run time: headless windows, sound, speech, serial ports, namespaces, real test images
  xvfb xauth libgl1-mesa-dri espeak-ng sox socat iproute2 procps opencv-doc python3
  # a second speech synthesiser: the recogniser's test voices that were never tuned on
  flite
  # a sound server with a null sink: the microphone tests' capture device
  pulseaudio pulseaudio-utils
  # real consumers of igms export's files: check_urdf (URDF), assimp info (OBJ, STL, glTF)
  liburdfdom-tools assimp-utils
  # deployment checks: units (systemd-analyze), compose files, the package (deploy/check-package.sh)
  systemd docker-compose dpkg-dev lintian
)

# What the installed programs load (each program's NEEDED entries, libc aside), and the
# data they read (the speech model).
RUNTIME_PACKAGES=(
  libstdc++6 libprotobuf32 libyaml-cpp0.7 libspdlog1.10 libfmt9
  libboost-program-options1.74.0
  libopencv-core406 libopencv-imgproc406 libopencv-imgcodecs406 libopencv-calib3d406
  libopencv-videoio406
  libopenal1 libsndfile1 libsqlite3-0 libssl3
  # the window: GLFW, OpenGL and EGL, and Mesa to draw offscreen without a GPU
  libglfw3 libopengl0 libegl1 libegl-mesa0 libgl1-mesa-dri
  # igms-control --xvfb: a virtual X server of its own where there is no display
  xvfb
  libpocketsphinx3 libsphinxbase3 pocketsphinx-en-us
  # the sound server's fallback device, and iproute2 for deploy/lab up --here
  procps iproute2
)

# Node.js and npm run Khronos' glTF validator in the export tests (npm gltf-validator, into
# the build tree). A machine with its own Node (from NodeSource, nvm) keeps it: Debian's
# nodejs would conflict with it.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  PACKAGES+=(nodejs npm)
fi
if [ "$RUNTIME" = 1 ]; then PACKAGES=("${RUNTIME_PACKAGES[@]}"); fi
if [ "$LIST" = 1 ]; then
  printf '%s\n' "${PACKAGES[@]}"
  exit 0
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "install-deps: done"
