// Reads a file written by retreat_mcap_sample with the reference MCAP reader (@mcap/core, the
// TypeScript library Foxglove uses), both ways: indexed (summary, chunk indexes, message
// indexes) and streamed record by record with every CRC checked (the data section's here, with
// @foxglove/crc). Decodes the CDR messages with
// @foxglove/omgidl-serialization from the schema's IDL text. Exits 1 on the first mismatch.
//
//   node read_mcap.mjs NODE_MODULES FILE MESSAGES MIN_CHUNKS
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

const [nodeModules, file, messagesArg, minChunksArg] = process.argv.slice(2);
const require = createRequire(path.join(nodeModules, "noop.js"));
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { loadDecompressHandlers } = require("@mcap/support");
const { parseIDL } = require("@foxglove/omgidl-parser");
const { MessageReader } = require("@foxglove/omgidl-serialization");
const { crc32 } = require("@foxglove/crc");

const expectedMessages = Number(messagesArg);
const minChunks = Number(minChunksArg);
let failures = 0;
function check(ok, what) {
  if (!ok) {
    console.error(`read_mcap: ${what}`);
    failures += 1;
  }
}

const bytes = new Uint8Array(readFileSync(file));
const decompressHandlers = await loadDecompressHandlers();
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};

// Indexed: the summary section must be complete and consistent.
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
check(reader.header.library === "retreat", `library ${reader.header.library}`);
check(reader.statistics?.messageCount === BigInt(expectedMessages),
      `statistics.messageCount ${reader.statistics?.messageCount}, expected ${expectedMessages}`);
check(reader.chunkIndexes.length >= minChunks, `${reader.chunkIndexes.length} chunks, expected at least ${minChunks}`);
check(reader.channelsById.size === 3, `${reader.channelsById.size} channels`);
const topics = [...reader.channelsById.values()].map((c) => c.topic).join(",");
check(topics === "/frames,/decisions,/log", `topics ${topics}`);
check(reader.channelsById.get(0).metadata.get("vendor") === "test", "channel 0's metadata");
const schema = reader.schemasById.get(1);
check(schema?.name === "retreat::msg::Sample" && schema?.encoding === "omgidl", "schema 1");
const decode = new MessageReader("retreat::msg::Sample", parseIDL(new TextDecoder().decode(schema.data)));

let i = 0;
for await (const m of reader.readMessages()) {
  const at = `message ${i}`;
  check(m.channelId === i % 3, `${at}: channel ${m.channelId}`);
  check(m.sequence === i, `${at}: sequence ${m.sequence}`);
  check(m.logTime === 1000000n * BigInt(i) + 7n, `${at}: log time ${m.logTime}`);
  check(m.publishTime === m.logTime - 3n, `${at}: publish time ${m.publishTime}`);
  if (i % 3 === 2) {
    const text = new TextDecoder().decode(m.data);
    check(text === `{"i":${i}}`, `${at}: ${text}`);
  } else {
    const sample = decode.readMessage(m.data);
    check(sample.robot === i && sample.value === i / 2, `${at}: ${JSON.stringify(sample)}`);
  }
  i += 1;
  if (failures > 10) break;
}
check(i === expectedMessages, `read ${i} messages, expected ${expectedMessages}`);
const metadata = [];
for await (const m of reader.readMetadata()) metadata.push(m);
check(metadata.length === 2 && metadata[0].name === "retreat" && metadata[0].metadata.get("seed") === "1" &&
      metadata[1].metadata.get("messages") === String(expectedMessages), "metadata");

// Streamed: every record in file order, the chunks' and the data section's CRCs checked.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const counts = {};
for (let record; (record = stream.nextRecord()) !== undefined;) counts[record.type] = (counts[record.type] ?? 0) + 1;
check(stream.done(), "the stream reader did not reach the closing magic");
// The reader does not check the Data End record's CRC of the data section: check it here. The
// data section ends where Data End (opcode, length, u32: 13 bytes) begins, just before the summary.
const dataEnd = Number(reader.footer.summaryStart) - 13;
const dataSectionCrc = new DataView(bytes.buffer, bytes.byteOffset + dataEnd + 9, 4).getUint32(0, true);
check(bytes[dataEnd] === 0x0f, "no Data End record before the summary");
check(dataSectionCrc === crc32(bytes.subarray(0, dataEnd)), `data section CRC ${dataSectionCrc}`);
check((counts.Message ?? 0) === expectedMessages, `stream: ${counts.Message ?? 0} messages`);
check(counts.Footer === 1 && counts.DataEnd === 1 && counts.Header === 1, `stream: ${JSON.stringify(counts)}`);

if (failures > 0) process.exit(1);
console.log(`read_mcap: ok, ${i} messages in ${reader.chunkIndexes.length} chunks, ${JSON.stringify(counts)}`);
