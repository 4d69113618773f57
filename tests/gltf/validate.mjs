// Runs the Khronos glTF-Validator (npm gltf-validator, pinned in package-lock.json) over each
// .glb / .gltf named on the command line, external resources (.bin, PNGs) included, and exits 1
// if any file has an error or a warning. Prints one line per file and a total.
//
//   node validate.mjs FILE...
import fs from 'node:fs';
import path from 'node:path';
import validator from 'gltf-validator';

let bad = 0;
let errors = 0;
let warnings = 0;
for (const file of process.argv.slice(2)) {
  const dir = path.dirname(file);
  const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
    uri: path.basename(file),
    maxIssues: 0,
    writeTimestamp: false,
    externalResourceFunction: (uri) =>
      new Promise((resolve, reject) => {
        fs.readFile(path.join(dir, decodeURIComponent(uri)), (err, data) =>
          err ? reject(err.toString()) : resolve(new Uint8Array(data)));
      }),
  });
  const i = report.issues;
  errors += i.numErrors;
  warnings += i.numWarnings;
  console.log(`${file}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
              `${i.numHints} hints (glTF-Validator ${report.validatorVersion})`);
  for (const m of i.messages) {
    if (m.severity <= 1) {  // 0 error, 1 warning
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} at ${m.pointer}: ${m.message}`);
      bad += 1;
    } else if (process.env.GLTF_VALIDATE_VERBOSE) {
      console.log(`  ${m.severity === 2 ? 'info' : 'hint'} ${m.code} at ${m.pointer}: ${m.message}`);
    }
  }
}
console.log(`total: ${errors} errors, ${warnings} warnings on ${process.argv.length - 2} files`);
process.exit(bad ? 1 : 0);
