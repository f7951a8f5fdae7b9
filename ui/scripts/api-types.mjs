// Writes src/api/openapi.ts, the API's types, from the server's description (/openapi.json)
// with openapi-typescript. The description comes from `python -m twinlink.openapi`,
// which builds the app without starting a server. With --check, nothing is written: the run
// fails when the committed file differs (tests/integration/test_openapi_contract.py runs it).
//   npm run api-types            (make ui-types)
//   TWINLINK_PYTHON=path/to/python npm run api-types   (default: ../.venv/bin/python)
import { execFileSync } from "node:child_process";
import { readFileSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import openapiTS, { astToString } from "openapi-typescript";

const target = fileURLToPath(new URL("../src/api/openapi.ts", import.meta.url));
const python = process.env.TWINLINK_PYTHON ?? fileURLToPath(new URL("../../.venv/bin/python", import.meta.url));
const HEADER =
  "// Generated from the server's /openapi.json by ui/scripts/api-types.mjs (npm run api-types,\n" +
  "// make ui-types): do not edit. Convenient names for these types are in types.ts.\n\n";

const description = execFileSync(python, ["-m", "twinlink.openapi"], {
  encoding: "utf8",
  maxBuffer: 64 * 1024 * 1024,
});
// defaultNonNullable off: a field with a default may be left out of a request, and an answer
// leaves out such a field when it does not apply (`kept_state`, `dry_run`).
const ast = await openapiTS(JSON.parse(description), { defaultNonNullable: false });
const text = HEADER + astToString(ast);

if (process.argv.includes("--check")) {
  let committed = "";
  try {
    committed = readFileSync(target, "utf8");
  } catch {
    // missing: stale too
  }
  if (committed !== text) {
    console.error("ui/src/api/openapi.ts is not what the API describes now: run `make ui-types` and commit it.");
    process.exit(1);
  }
  console.log("ui/src/api/openapi.ts is current");
} else {
  writeFileSync(target, text);
  console.log(`wrote ${target}`);
}
