// Writes an MCAP file with the reference writer (@mcap/core's McapWriter, zstd chunks from
// @foxglove/wasm-zstd), for retreat's reader to read (tests/recording, McapReader.*), and prints
// what it wrote, one line per record of interest, in the form retreat_mcap_list prints what it
// read. Three channels: an omgidl schema, a jsonschema one, and one without a schema; messages
// of 0..40 bytes, chunks of 1 KiB (many of them); two metadata records.
//
//   node write_mcap.mjs NODE_MODULES FILE MESSAGES > expected.txt
import { createRequire } from "node:module";
import { open } from "node:fs/promises";
import path from "node:path";

const [nodeModules, file, count] = process.argv.slice(2);
const require = createRequire(path.join(nodeModules, "noop.js"));
const { McapWriter } = require("@mcap/core");
const zstd = require("@foxglove/wasm-zstd");
await zstd.isLoaded;

const handle = await open(file, "w");
let position = 0n;
const writable = {
  write: async (buffer) => {
    await handle.write(buffer);
    position += BigInt(buffer.byteLength);
  },
  position: () => position,
};
const writer = new McapWriter({
  writable,
  chunkSize: 1024,
  compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }),
});
await writer.start({ profile: "", library: "mcap-js reference writer" });
const text = (s) => new TextEncoder().encode(s);
const lines = [];
const idl = await writer.registerSchema({ name: "test::Sample", encoding: "omgidl", data: text("module test { struct Sample { uint32 x; }; };") });
const json = await writer.registerSchema({ name: "test.Json", encoding: "jsonschema", data: text('{"type":"object"}') });
const channels = [
  await writer.registerChannel({ topic: "/a", schemaId: idl, messageEncoding: "cdr", metadata: new Map([["k", "v"]]) }),
  await writer.registerChannel({ topic: "/b", schemaId: json, messageEncoding: "json", metadata: new Map() }),
  await writer.registerChannel({ topic: "/c", schemaId: 0, messageEncoding: "raw", metadata: new Map() }),
];
const topics = ["/a", "/b", "/c"];
await writer.addMetadata({ name: "first", metadata: new Map([["seed", "7"], ["empty", ""]]) });
for (let i = 0; i < Number(count); i += 1) {
  const channel = i % 3;
  const data = new Uint8Array(i % 41).map((_, j) => (i * 31 + j * 7) & 0xff);
  const logTime = 1_000_000_000n + BigInt(i) * 1000n;
  await writer.addMessage({ channelId: channels[channel], sequence: i, logTime, publishTime: logTime - 5n, data });
  lines.push(`message ${topics[channel]} ${i} ${logTime} ${logTime - 5n} ${Buffer.from(data).toString("hex")}`);
}
await writer.addMetadata({ name: "last", metadata: new Map([["messages", String(count)]]) });
await writer.end();
await handle.close();
console.log(lines.join("\n"));
console.log("metadata first empty= seed=7");
console.log(`metadata last messages=${count}`);
console.log("channel /a test::Sample omgidl cdr k=v");
console.log("channel /b test.Json jsonschema json");
console.log("channel /c - - raw");
// The verdict line node_verdict.sh waits for, on stderr: stdout is the listing compared.
console.error(`write_mcap: ok, ${count} messages`);
