// Two recordings of the same lockstep run (same scenario and seed) made over different vendors:
// the CDR payloads of every robot's frames and answers must be the same encoding. Cyclone DDS's
// recorder keeps the bytes it received; Fast DDS's serializes each sample again with the
// generated type (docs/recording.md). The one difference XCDR1 allows: Cyclone DDS pads the
// body to a multiple of 4 bytes and says how many it added in the encapsulation options' last
// two bits; Fast DDS adds none. So each payload is compared without that padding and with the
// options zeroed; everything else must be byte for byte the same. A re-sent frame may appear
// twice in one file, so the payloads are compared as sets per channel.
//
//   node compare_payloads.mjs NODE_MODULES A.mcap B.mcap
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

const [nodeModules, fileA, fileB] = process.argv.slice(2);
const require = createRequire(path.join(nodeModules, "noop.js"));
const { McapIndexedReader } = require("@mcap/core");
const { loadDecompressHandlers } = require("@mcap/support");
const decompressHandlers = await loadDecompressHandlers();

/// The payload without its end padding (options & 3 bytes, XCDR1) and with the options zeroed.
function normalized(data) {
  const padding = data.length >= 4 ? data[3] & 0x03 : 0;
  const body = Buffer.from(data.subarray(0, data.length - padding));
  if (body.length >= 4) body[2] = body[3] = 0;
  return body.toString("hex");
}

async function payloads(file) {
  const bytes = new Uint8Array(readFileSync(file));
  const reader = await McapIndexedReader.Initialize({
    readable: { size: async () => BigInt(bytes.length), read: async (o, l) => bytes.subarray(Number(o), Number(o + l)) },
    decompressHandlers,
  });
  const out = new Map();
  for await (const m of reader.readMessages()) {
    const topic = reader.channelsById.get(m.channelId).topic;
    if (!/\/robot_\d+\/(proximity|decision|plan)$/.test(topic)) continue;
    if (!out.has(topic)) out.set(topic, new Set());
    out.get(topic).add(normalized(m.data));
  }
  return out;
}

const [a, b] = [await payloads(fileA), await payloads(fileB)];
let failures = 0, compared = 0;
const topics = new Set([...a.keys(), ...b.keys()]);
for (const topic of topics) {
  const x = a.get(topic) ?? new Set(), y = b.get(topic) ?? new Set();
  const onlyA = [...x].filter((p) => !y.has(p)), onlyB = [...y].filter((p) => !x.has(p));
  compared += x.size;
  if (onlyA.length + onlyB.length > 0) {
    failures += 1;
    if (failures <= 10) {
      console.error(`compare_payloads: ${topic}: ${onlyA.length} payloads only in ${fileA}, ${onlyB.length} only in ${fileB}` +
                    (onlyA.length ? ` (e.g. ${onlyA[0]})` : "") + (onlyB.length ? ` (e.g. ${onlyB[0]})` : ""));
    }
  }
}
if (topics.size === 0) {
  console.error("compare_payloads: no frames or answers in either file");
  process.exit(1);
}
if (failures > 0) process.exit(1);
console.log(`compare_payloads: ok, ${compared} distinct payloads on ${topics.size} channels, the same encoding in both`);
