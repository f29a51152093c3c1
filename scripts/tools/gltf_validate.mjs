// gltf_validate.mjs DIR FILE... — runs the Khronos glTF validator installed
// under DIR (npm --prefix DIR) on each file; .gltf files get their external
// .bin/.png files from next to them. Prints "FILE: N errors, M warnings" (and
// every error and warning) and exits 1 when any file has an error.
import { createRequire } from 'node:module';
import fs from 'node:fs';
import path from 'node:path';

const [dir, ...files] = process.argv.slice(2);
const validator = createRequire(path.join(path.resolve(dir), 'node_modules', 'x.js'))('gltf-validator');
let failed = false;
for (const file of files) {
  let report;
  try {
    report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
      uri: path.basename(file),
      maxIssues: 0,
      writeTimestamp: false,
      externalResourceFunction: (uri) =>
        fs.promises.readFile(path.resolve(path.dirname(file), decodeURIComponent(uri)))
          .then((data) => new Uint8Array(data)),
    });
  } catch (e) {
    console.log(`${file}: validator failed: ${e}`);
    failed = true;
    continue;
  }
  const { numErrors, numWarnings, messages } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings`);
  for (const m of messages)
    if (m.severity <= 1)
      console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
