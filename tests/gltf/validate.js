// Validates a glTF file with the Khronos glTF validator (npm package gltf-validator).
// Usage: node tests/gltf/validate.js FILE.gltf
// Prints the validator's issue counts and messages as JSON; exits 0 when it reports no error,
// 1 when it reports errors, 2 when the file cannot be read or validated at all.
const fs = require('fs');
const path = require('path');
const validator = require('gltf-validator');

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate.js FILE.gltf');
  process.exit(2);
}
const folder = path.dirname(path.resolve(file));
const readResource = (uri) =>
  new Promise((resolve, reject) => {
    fs.readFile(path.join(folder, decodeURIComponent(uri)), (err, data) => (err ? reject(err.toString()) : resolve(new Uint8Array(data))));
  });

validator
  .validateBytes(new Uint8Array(fs.readFileSync(file)), { uri: path.basename(file), externalResourceFunction: readResource })
  .then((report) => {
    console.log(JSON.stringify(report.issues, null, 1));
    process.exit(report.issues.numErrors > 0 ? 1 : 0);
  })
  .catch((error) => {
    console.error('validation failed: ' + error);
    process.exit(2);
  });
