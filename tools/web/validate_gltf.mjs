// Validates a .glb or .gltf file with the Khronos glTF Validator (npm gltf-validator, pinned in
// package.json) and prints its report as one JSON object: {"file", "errors", "warnings", "infos",
// "hints", "messages": [the first 50: {"code", "severity", "pointer", "message"}], "info": the
// validator's summary (triangles, draw calls, extensions)}. Exit status: 0 with no error, 1 with
// errors, 2 when the file cannot be read. External resources resolve beside the file.
// Usage: node tools/web/validate_gltf.mjs FILE
import { readFile } from 'node:fs/promises';
import path from 'node:path';
import validator from 'gltf-validator';

const file = process.argv[2];
if (!file) {
  console.error('usage: node validate_gltf.mjs FILE.glb|FILE.gltf');
  process.exit(2);
}
let bytes;
try {
  bytes = new Uint8Array(await readFile(file));
} catch (e) {
  console.error(`${file}: ${e.message}`);
  process.exit(2);
}
const report = await validator.validateBytes(bytes, {
  uri: path.basename(file),
  maxIssues: 0,
  externalResourceFunction: (uri) =>
    readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
});
const severity = ['error', 'warning', 'info', 'hint'];
const out = {
  file,
  errors: report.issues.numErrors,
  warnings: report.issues.numWarnings,
  infos: report.issues.numInfos,
  hints: report.issues.numHints,
  messages: report.issues.messages.slice(0, 50).map((m) => ({
    code: m.code, severity: severity[m.severity] ?? m.severity, pointer: m.pointer, message: m.message,
  })),
  info: report.info,
};
console.log(JSON.stringify(out, null, 1));
process.exit(report.issues.numErrors > 0 ? 1 : 0);
