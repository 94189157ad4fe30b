// Validates .glb files with the Khronos glTF validator; exit 1 if any has an error.
// usage: node scripts/validate-gltf.js FILE.glb...
const fs = require('fs');
const path = require('path');
const validator = require(path.resolve(__dirname, '../target/gltf-validator/node_modules/gltf-validator'));

(async () => {
  let failed = false;
  for (const file of process.argv.slice(2)) {
    const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)));
    const issues = report.issues;
    console.log(`${file}: ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos`);
    for (const m of issues.messages) {
      if (m.severity <= 1) console.log(`  ${m.code} ${m.pointer || ''}: ${m.message}`);
    }
    if (issues.numErrors > 0) failed = true;
  }
  process.exit(failed ? 1 : 0);
})();
