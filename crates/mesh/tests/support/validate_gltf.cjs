// Validates glTF files with the Khronos glTF-Validator (npm package `gltf-validator`) and prints
// one JSON line per file: {"file", "errors", "warnings", "infos", "messages"} (the first 20
// messages). The module is found through GLTF_VALIDATOR_MODULE (its folder) or Node's usual
// lookup (NODE_PATH, a node_modules folder); exit code 3 when it is not installed.
// Usage: node validate_gltf.cjs FILE...
const fs = require("fs");
const path = require("path");

let validator;
try {
  validator = require(process.env.GLTF_VALIDATOR_MODULE || "gltf-validator");
} catch (e) {
  console.error("gltf-validator not found: " + e.message);
  process.exit(3);
}

async function main() {
  for (const file of process.argv.slice(2)) {
    const data = new Uint8Array(fs.readFileSync(file));
    const report = await validator.validateBytes(data, {
      uri: path.basename(file),
      externalResourceFunction: (uri) =>
        new Promise((resolve, reject) => {
          const from = path.join(path.dirname(file), decodeURIComponent(uri));
          fs.readFile(from, (err, bytes) =>
            err ? reject(err.toString()) : resolve(new Uint8Array(bytes))
          );
        }),
    });
    const issues = report.issues;
    console.log(
      JSON.stringify({
        file,
        errors: issues.numErrors,
        warnings: issues.numWarnings,
        infos: issues.numInfos,
        messages: issues.messages.slice(0, 20),
      })
    );
  }
}

main().catch((e) => {
  console.error(e);
  process.exit(2);
});
