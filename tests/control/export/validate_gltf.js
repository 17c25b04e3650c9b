// Khronos' glTF validator (npm gltf-validator, a library) over the files given: prints each
// file's counts and its errors and warnings; exits 1 when any file has one, 2 when it cannot
// run. A .gltf's buffer and a file's images are read from beside it.
'use strict';
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

async function main() {
  let bad = 0;
  for (const file of process.argv.slice(2)) {
    const folder = path.dirname(file);
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file),
      externalResourceFunction: (uri) =>
        new Promise((resolve, reject) => {
          try {
            resolve(new Uint8Array(fs.readFileSync(path.join(folder, decodeURIComponent(uri)))));
          } catch (e) {
            reject(e.toString());
          }
        }),
    });
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
                `${issues.numInfos} infos, ${issues.numHints} hints`);
    for (const m of issues.messages) {
      // Severity 0 is an error, 1 a warning; infos and hints are listed too, to read.
      console.log(`  ${['error', 'warning', 'info', 'hint'][m.severity]} ${m.code} ` +
                  `${m.pointer || ''}: ${m.message}`);
    }
    if (issues.numErrors || issues.numWarnings) bad = 1;
  }
  return bad;
}

main().then((code) => process.exit(code), (e) => {
  console.error(`validate_gltf: ${e}`);
  process.exit(2);
});
