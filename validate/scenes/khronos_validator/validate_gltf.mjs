// Khronos glTF Validator (npm `gltf-validator`) on every file named on the command line; prints one JSON array:
// per file its issue counts and messages (code, severity 0 error … 3 hint, pointer, message). Run from the
// suite's engines folder (validate/setup/paths.py node_scripts) so the bare import resolves.
import { readFile } from "node:fs/promises";
import path from "node:path";
import validator from "gltf-validator";

const out = [];
for (const file of process.argv.slice(2)) {
  const data = new Uint8Array(await readFile(file));
  const report = await validator.validateBytes(data, {
    uri: path.basename(file),
    maxIssues: 200,
    externalResourceFunction: (uri) =>
      readFile(path.join(path.dirname(file), decodeURIComponent(uri))).then((b) => new Uint8Array(b)),
  });
  const issues = report.issues;
  out.push({
    file,
    validatorVersion: report.validatorVersion,
    numErrors: issues.numErrors,
    numWarnings: issues.numWarnings,
    numInfos: issues.numInfos,
    numHints: issues.numHints,
    messages: issues.messages.map((m) => ({ code: m.code, severity: m.severity, pointer: m.pointer ?? null,
                                            message: m.message })),
  });
}
process.stdout.write(JSON.stringify(out));
