// Validate a glTF or GLB file with Khronos's glTF validator (npm: gltf-validator),
// installed by tools/system-packages.sh into tools/node. Prints the report's issue
// counts and messages; exits 1 when the report has errors, 2 when the file cannot
// be read or validated.
//
//     node tools/gltf-validate.mjs runs/eel2d/swim.glb
import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const validator = createRequire(path.join(here, "node", "package.json"))("gltf-validator");

const file = process.argv[2];
if (!file) {
  console.error("usage: node tools/gltf-validate.mjs FILE.glb|FILE.gltf");
  process.exit(2);
}
try {
  const report = await validator.validateBytes(new Uint8Array(await readFile(file)), {
    uri: file,
    externalResourceFunction: (uri) =>
      readFile(path.resolve(path.dirname(file), decodeURIComponent(uri))),
  });
  const issues = report.issues;
  console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ` +
              `${issues.numInfos} infos, ${issues.numHints} hints (validator ${report.validatorVersion})`);
  for (const message of issues.messages) {
    console.log(`  [${message.severity}] ${message.code} at ${message.pointer ?? "-"}: ${message.message}`);
  }
  process.exit(issues.numErrors > 0 ? 1 : 0);
} catch (error) {
  console.error(`${file}: could not be validated: ${error}`);
  process.exit(2);
}
