// Validates glTF files with the Khronos glTF-Validator (npm gltf-validator, pinned in
// package.json) and prints one line per file: errors, warnings, infos, hints, and the first
// issues. Exit status 1 if any file has an error or a warning (issue 31: 0 and 0 required).
// Usage: node scripts/gltf/check_gltf.mjs FILE.glb...
import { readFile } from "node:fs/promises";
import validator from "gltf-validator";

let failed = false;
for (const path of process.argv.slice(2)) {
  const bytes = new Uint8Array(await readFile(path));
  const report = await validator.validateBytes(bytes, { maxIssues: 50 });
  const i = report.issues;
  console.log(`${path}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages.filter((m) => m.severity <= 1).slice(0, 10))
    console.log(`  ${m.severity === 0 ? "error" : "warning"} ${m.code} at ${m.pointer ?? ""}: ${m.message}`);
  if (i.numErrors > 0 || i.numWarnings > 0) failed = true;
}
process.exit(failed ? 1 : 0);
