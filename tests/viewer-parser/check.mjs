// Runs the JSON-schema parser of Foxglove Studio 1.48.0 (the viewers'
// own code, `parseChannel` and `parseJsonSchema` of its `mcap-support`
// package, MPL-2.0) on every channel and every message of MCAP files, as
// the app does when it opens them. The parser comes from the npm package
// `@foxglove/studio-base@1.48.0` (pinned with its integrity in
// package-lock.json, installed by `npm ci`): its prebuilt bundle holds
// each source module as a marked section, which is taken as is and run.
//
// Usage: node check.mjs DUMP.json
// DUMP.json (written by tests/tests/viewers.rs from the MCAP files):
//   {"files": [{"name", "channels": [{"id", "topic", "messageEncoding",
//     "schema": {"name", "encoding", "data"}}], "messages": [{"channel",
//     "sequence", "data"}]}]}   (schema and message data in hex)
// Prints one line per channel; exits 1 if the viewer refuses a channel or
// cannot decode a message, or if a decoded message has a field that the
// channel's datatypes do not describe or a value of another type.

import { readFileSync, readdirSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const assets = join(here, "node_modules", "@foxglove", "studio-base", "assets");

/** The text of the bundle's section for source module `path`. */
function moduleSection(bundle, path) {
  const start = bundle.indexOf(`;// CONCATENATED MODULE: ${path}\n`);
  if (start < 0) {
    throw new Error(`${path} is not in the bundle`);
  }
  const next = /\n(;\/\/ CONCATENATED MODULE: |\/\/ EXTERNAL MODULE: )/g;
  next.lastIndex = start + 1;
  const end = next.exec(bundle);
  return bundle.slice(start, end ? end.index : undefined);
}

/** `parseChannel` of the viewer, from the asset that bundles it. */
function loadParser() {
  const marker = "CONCATENATED MODULE: ../mcap-support/src/parseJsonSchema.ts";
  const files = readdirSync(assets).filter((f) => f.endsWith(".js"));
  // The worker chunks are small; the 56 MB main bundle holds a copy too.
  files.sort((a, b) => (a === "index.js") - (b === "index.js"));
  for (const f of files) {
    const bundle = readFileSync(join(assets, f), "utf8");
    if (!bundle.includes(marker)) {
      continue;
    }
    const source = [
      moduleSection(bundle, "../mcap-support/src/parseJsonSchema.ts"),
      moduleSection(bundle, "../mcap-support/src/parseChannel.ts"),
    ].join("\n");
    for (const name of ["function parseJsonSchema(", "function parseChannel("]) {
      if (!source.includes(name)) {
        throw new Error(`${f}: no ${name}`);
      }
    }
    // `base64` is the bundle's @protobufjs/base64, used only by fields with
    // `contentEncoding: base64`.
    const base64 = {
      length: (s) => Buffer.from(s, "base64").length,
      decode: (s, out, offset) => {
        const bytes = Buffer.from(s, "base64");
        out.set(bytes, offset);
        return bytes.length;
      },
    };
    const make = new Function("base64", `${source}\nreturn parseChannel;`);
    return { parseChannel: make(base64), asset: f };
  }
  throw new Error(`no asset of ${assets} holds the parser (run npm ci in ${here})`);
}

const kinds = {
  bool: (v) => typeof v === "boolean",
  string: (v) => typeof v === "string",
  float64: (v) => typeof v === "number",
  uint32: (v) => typeof v === "number",
  uint8: (v) => typeof v === "number",
};

/** What in `value` the datatype `type` does not describe, at `path`. */
function undescribed(datatypes, type, value, path, out) {
  const def = datatypes.get(type);
  if (def == undefined) {
    out.push(`${path}: no datatype ${type}`);
    return;
  }
  if (value == null || typeof value !== "object" || Array.isArray(value)) {
    out.push(`${path}: ${JSON.stringify(value)} is not an object`);
    return;
  }
  const fields = new Map(def.definitions.filter((d) => !d.isConstant).map((d) => [d.name, d]));
  for (const [name, v] of Object.entries(value)) {
    const field = fields.get(name);
    const at = `${path}.${name}`;
    if (field == undefined) {
      out.push(`${at}: not a field of ${type}`);
      continue;
    }
    const items = field.isArray ? v : [v];
    if (!Array.isArray(items) && !(items instanceof Uint8Array)) {
      out.push(`${at}: ${JSON.stringify(v)} is not an array`);
      continue;
    }
    for (const [i, item] of Array.from(items).entries()) {
      const where = field.isArray ? `${at}[${i}]` : at;
      if (field.isComplex) {
        undescribed(datatypes, field.type, item, where, out);
      } else if (!kinds[field.type]?.(item)) {
        out.push(`${where}: ${JSON.stringify(item)} is not a ${field.type}`);
      }
    }
  }
}

function checkFile(parseChannel, file) {
  const problems = [];
  const parsed = new Map();
  for (const ch of file.channels) {
    const schema = {
      name: ch.schema.name,
      encoding: ch.schema.encoding,
      data: new Uint8Array(Buffer.from(ch.schema.data, "hex")),
    };
    try {
      parsed.set(ch.id, parseChannel({ messageEncoding: ch.messageEncoding, schema }));
    } catch (e) {
      problems.push(`${file.name}: channel ${ch.id} ${ch.topic} refused: ${e.message}`);
    }
  }
  const counts = new Map();
  for (const m of file.messages) {
    const ch = file.channels.find((c) => c.id === m.channel);
    const p = parsed.get(m.channel);
    if (ch == undefined || p == undefined) {
      problems.push(`${file.name}: message ${m.sequence} on channel ${m.channel} without channel info`);
      continue;
    }
    let value;
    try {
      value = p.deserialize(new Uint8Array(Buffer.from(m.data, "hex")));
    } catch (e) {
      problems.push(`${file.name}: ${ch.topic} message ${m.sequence} not decoded: ${e.message}`);
      continue;
    }
    const found = [];
    undescribed(p.datatypes, ch.schema.name, value, ch.topic, found);
    for (const f of found.slice(0, 5)) {
      problems.push(`${file.name}: message ${m.sequence}: ${f}`);
    }
    counts.set(ch.topic, (counts.get(ch.topic) ?? 0) + 1);
  }
  for (const ch of file.channels) {
    const types = parsed.get(ch.id)?.datatypes.size ?? 0;
    console.log(
      `${file.name} ${ch.topic} ${ch.schema.name}: ${types} datatypes, ${counts.get(ch.topic) ?? 0} messages decoded`,
    );
  }
  return problems;
}

const dump = JSON.parse(readFileSync(process.argv[2], "utf8"));
const { parseChannel, asset } = loadParser();
console.log(`parser: @foxglove/studio-base 1.48.0 assets/${asset}`);
const problems = dump.files.flatMap((f) => checkFile(parseChannel, f));
for (const p of problems) {
  console.log(`PROBLEM ${p}`);
}
process.exit(problems.length === 0 ? 0 : 1);
