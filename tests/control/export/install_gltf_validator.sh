#!/bin/sh
# CTest fixture: installs npm's gltf-validator into FOLDER (the build tree's) unless it is
# there already. Never fails: without node, npm or the registry, it says why, and the
# validator test skips.
folder="$1"
if [ -f "$folder/node_modules/gltf-validator/package.json" ]; then
  echo "gltf-validator: already in $folder"
  exit 0
fi
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  echo "gltf-validator: node or npm is missing (deploy/install-deps.sh installs them); the glTF validator test will skip"
  exit 0
fi
mkdir -p "$folder"
if timeout 120 npm install --prefix "$folder" --no-audit --no-fund --loglevel=error \
    gltf-validator@2.0.0-dev.3.10 >"$folder/npm-install.log" 2>&1; then
  echo "gltf-validator: installed in $folder"
else
  echo "gltf-validator: npm could not install it (the registry unreachable?); the glTF validator test will skip. npm said:"
  tail -5 "$folder/npm-install.log"
fi
exit 0
