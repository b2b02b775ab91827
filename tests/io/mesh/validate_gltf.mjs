// Validates a glTF or GLB file with the Khronos glTF validator (npm gltf-validator, installed by
// cmake/setup_web_tools.sh) and prints its report's counts as one line of JSON, with the first
// issues as "SEVERITY CODE POINTER: MESSAGE" (severity 0 error, 1 warning, 2 info, 3 hint).
// Usage: node validate_gltf.mjs NODE_MODULES FILE
import { readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';

const [modules, file] = process.argv.slice(2);
if (!modules || !file) {
  console.error('usage: node validate_gltf.mjs NODE_MODULES FILE');
  process.exit(2);
}
const require = createRequire(path.join(path.resolve(modules), 'validate_gltf.cjs'));
const validator = require('gltf-validator');
const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), {
  uri: path.basename(file),
  maxIssues: 100,
});
const issues = report.issues;
console.log(JSON.stringify({
  numErrors: issues.numErrors,
  numWarnings: issues.numWarnings,
  numInfos: issues.numInfos,
  numHints: issues.numHints,
  messages: issues.messages.slice(0, 20).map(
      (m) => `${m.severity} ${m.code} ${m.pointer ?? ''}: ${m.message}`),
}));
