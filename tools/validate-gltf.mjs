#!/usr/bin/env node
// Validates glTF files with the Khronos glTF-Validator (npm: gltf-validator,
// a dev dependency of web/): `node tools/validate-gltf.mjs FILE...`.
// Prints every error (and, with --warnings, every warning) as
// "FILE: CODE at POINTER: message"; exit 0 when no file has an error, 1 when
// one has, 2 on bad usage, 3 when the validator package is not installed
// (run `npm ci` in web/), so callers can tell a missing tool from a bad file.
// External resources (buffers, images) are read from the file's folder only.

import { readFile } from "node:fs/promises";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const args = process.argv.slice(2);
const showWarnings = args.includes("--warnings");
const files = args.filter((a) => a !== "--warnings");
if (files.length === 0 || files.some((f) => f.startsWith("-"))) {
  console.error("usage: node tools/validate-gltf.mjs [--warnings] FILE...");
  process.exit(2);
}

let validator;
try {
  const require = createRequire(path.join(here, "..", "web", "package.json"));
  validator = require("gltf-validator");
} catch (e) {
  console.error("validate-gltf: the gltf-validator package is not installed (run `npm ci` in web/)");
  process.exit(3);
}

let failed = false;
for (const file of files) {
  let bytes;
  try {
    bytes = await readFile(file);
  } catch (e) {
    console.error(`${file}: cannot be read (${e.code ?? e.message})`);
    failed = true;
    continue;
  }
  const folder = path.resolve(path.dirname(file));
  let report;
  try {
    report = await validator.validateBytes(new Uint8Array(bytes), {
      uri: path.basename(file),
      maxIssues: 0,  // every issue
      externalResourceFunction: async (uri) => {
        const target = path.resolve(folder, decodeURIComponent(uri));
        if (path.relative(folder, target).startsWith("..")) throw new Error(`${uri} is outside the file's folder`);
        return new Uint8Array(await readFile(target));
      },
    });
  } catch (e) {
    console.error(`${file}: not validated: ${e}`);
    failed = true;
    continue;
  }
  const { numErrors, numWarnings, messages } = report.issues;
  for (const m of messages) {
    if (m.severity === 0 || (showWarnings && m.severity === 1)) {
      const kind = m.severity === 0 ? "error" : "warning";
      console.log(`${file}: ${kind} ${m.code}${m.pointer ? " at " + m.pointer : ""}: ${m.message}`);
    }
  }
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings`);
  if (numErrors > 0) failed = true;
}
process.exit(failed ? 1 : 0);
