// Checks a run's recording (retreat-launch --record) with tools retreat did not write: reads the
// MCAP file with @mcap/core (indexed, and streamed with every CRC checked), decodes every message
// of every channel with @foxglove/omgidl-serialization from the schema's IDL text, and compares
// what it holds with the run directory the arena wrote:
//   - metadata "retreat" names the run's scenario, seed and vendor; "retreat.recorder" counts
//     every message and no drop;
//   - every per-robot message carries its topic's robot id;
//   - lockstep: every frame a robot got was answered (decisions and plans), every answer answers
//     a recorded frame (by its time), and the arena's count of answers received (summary.json
//     decisions_received) lies between the frames answered and the answers recorded, both
//     without those to `departed` frames, which the arena does not wait for (docs/protocol.md
//     §6). A frame the arena re-sent (its answer was late) may be answered twice, and the arena
//     does not count a repeated plan;
//   - the onsets on a robot's frames add up to its onsets in agents.csv;
//   - each robot's first retreating answer is at its tick in retreats.csv, and no other robot
//     has one;
//   - every telemetry sample equals telemetry.csv's row of its tick, and the telemetry and the
//     poses are there for exactly the ticks the arena publishes them (the first tick of each
//     run.telemetry_period, from telemetry.csv's times), the last one the run's last tick;
//   - every agent's last status agrees with agents.csv (retreated or not);
//   - the scene channel (`<prefix>/scene`) names foxglove.SceneUpdate with the JSON Schema of the
//     npm package @foxglove/schemas, every message on it is valid against that schema (ajv), and
//     there is one per poses sample, drawing the same robots at the same places.
// Exits 1 with one line per mismatch (at most 20), 0 with a one-line count.
//
//   node check_recording.mjs NODE_MODULES FILE RUN_DIR
import { createRequire } from "node:module";
import { readFileSync } from "node:fs";
import path from "node:path";

const [nodeModules, file, runDir] = process.argv.slice(2);
const require = createRequire(path.join(nodeModules, "noop.js"));
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { loadDecompressHandlers } = require("@mcap/support");
const { parseIDL } = require("@foxglove/omgidl-parser");
const { MessageReader } = require("@foxglove/omgidl-serialization");
const { SceneUpdate } = require("@foxglove/schemas/jsonschema");
const Ajv = require("ajv");

let failures = 0;
function check(ok, what) {
  if (ok) return;
  failures += 1;
  if (failures <= 20) console.error(`check_recording: ${what}`);
}

function csv(name) {
  const [head, ...rows] = readFileSync(path.join(runDir, name), "utf8").trim().split("\n");
  const keys = head.split(",");
  return rows.filter((r) => r.length > 0).map((r) => Object.fromEntries(r.split(",").map((v, i) => [keys[i], v])));
}
const summary = JSON.parse(readFileSync(path.join(runDir, "summary.json"), "utf8"));
const telemetryRows = new Map(csv("telemetry.csv").map((r) => [Number(r.tick), r]));
const agents = new Map(csv("agents.csv").map((r) => [Number(r.robot), r]));
const retreats = new Map(csv("retreats.csv").map((r) => [Number(r.robot), Number(r.tick)]));

const bytes = new Uint8Array(readFileSync(file));
const decompressHandlers = await loadDecompressHandlers();
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });

const metadata = new Map();
for await (const m of reader.readMetadata()) metadata.set(m.name, m.metadata);
const run = metadata.get("retreat");
check(run?.get("scenario") === summary.scenario, `metadata scenario ${run?.get("scenario")}`);
check(run?.get("seed") === String(summary.seed), `metadata seed ${run?.get("seed")}`);
check(run?.get("vendor") === summary.launch.arena_vendor, `metadata vendor ${run?.get("vendor")}`);
const recorder = metadata.get("retreat.recorder");
check(recorder?.get("dropped") === "0", `the recorder dropped ${recorder?.get("dropped")}`);
check(recorder?.get("messages") === String(reader.statistics.messageCount),
      `recorder counted ${recorder?.get("messages")}, statistics ${reader.statistics.messageCount}`);

const decoders = new Map();
let validateScene = null;
for (const [id, schema] of reader.schemasById) {
  const text = new TextDecoder().decode(schema.data);
  if (schema.name === "foxglove.SceneUpdate") {
    check(schema.encoding === "jsonschema", `schema ${schema.name}: encoding ${schema.encoding}`);
    check(JSON.stringify(JSON.parse(text)) === JSON.stringify(SceneUpdate),
          "the scene schema is not @foxglove/schemas' foxglove.SceneUpdate");
    validateScene = new Ajv({ strict: false, allErrors: true }).compile(SceneUpdate);
    continue;
  }
  check(schema.encoding === "omgidl", `schema ${schema.name}: encoding ${schema.encoding}`);
  decoders.set(id, new MessageReader(schema.name, parseIDL(text)));
}
check(validateScene !== null, "no foxglove.SceneUpdate schema");
const prefix = run?.get("prefix") ?? "retreat";
const perRobot = new RegExp(`^${prefix}/robot_(\\d+)/(proximity|decision|plan|tracked_pose)$`);
const expectedSchema = { proximity: "retreat::msg::ProximityFrame", decision: "retreat::msg::Decision",
                         plan: "retreat::msg::Decision", tracked_pose: "retreat::msg::Poses" };

const robots = new Map();  // id -> {frames, answers, onsets, firstRetreat, lastStatus}
const robot = (id) => {
  if (!robots.has(id)) robots.set(id, { frames: 0, departedFrames: 0, answers: 0, onsets: 0, firstRetreat: null, lastStatus: null,
                                        frameTimes: new Set(), answerTimes: new Set(), departedTimes: new Set() });
  return robots.get(id);
};
let messages = 0, telemetry = 0, poses = 0, lastTelemetryTick = -1;
const telemetryTicks = [], posesTicks = [];
const posesByTick = new Map(), sceneByTick = new Map();  // tick -> robots as "id x y" strings
for await (const m of reader.readMessages()) {
  messages += 1;
  const channel = reader.channelsById.get(m.channelId);
  const schema = reader.schemasById.get(channel.schemaId);
  if (channel.topic === `${prefix}/scene`) {
    check(channel.messageEncoding === "json" && schema.name === "foxglove.SceneUpdate",
          `${channel.topic}: ${channel.messageEncoding}, schema ${schema.name}`);
    let update;
    try {
      update = JSON.parse(new TextDecoder().decode(m.data));
    } catch (e) {
      check(false, `${channel.topic} message ${m.sequence}: not JSON (${e.message})`);
      continue;
    }
    if (validateScene && !validateScene(update)) {
      check(false, `${channel.topic} message ${m.sequence}: not a valid foxglove.SceneUpdate: ` +
                   JSON.stringify(validateScene.errors.slice(0, 2)));
      continue;
    }
    const robotsEntity = update.entities.find((e) => e.id === "robots");
    const tick = Number(robotsEntity?.metadata.find((kv) => kv.key === "tick")?.value);
    check(update.entities.some((e) => e.id === "domain" && e.lines.length === 1), `scene of tick ${tick}: no domain outline`);
    sceneByTick.set(tick, (robotsEntity?.cylinders ?? []).map((c, i) =>
      `${robotsEntity.texts[i]?.text} ${c.pose.position.x} ${c.pose.position.y}`).join(";"));
    continue;
  }
  let sample;
  try {
    sample = decoders.get(channel.schemaId).readMessage(m.data);
  } catch (e) {
    check(false, `${channel.topic} message ${m.sequence}: cannot decode (${e.message})`);
    continue;
  }
  const match = perRobot.exec(channel.topic);
  if (match) {
    const id = Number(match[1]);
    const kind = match[2];
    check(schema.name === expectedSchema[kind], `${channel.topic}: schema ${schema.name}`);
    if (kind === "proximity") {
      check(sample.robot_id === id, `${channel.topic}: a frame of robot ${sample.robot_id}`);
      const r = robot(id);
      if (!r.frameTimes.has(sample.time)) r.onsets += sample.new_onsets;  // a re-sent frame repeats its onsets
      r.frames += 1;
      r.frameTimes.add(sample.time);
      if (sample.phase === 3) r.departedTimes.add(sample.time);
    } else if (kind === "decision" || kind === "plan") {
      check(sample.robot_id === id, `${channel.topic}: an answer of robot ${sample.robot_id}`);
      const r = robot(id);
      r.answers += 1;
      r.answerTimes.add(sample.time);
      if (r.departedTimes.has(sample.time)) r.departedFrames += 1;
      // A plan may put its retreat past the run's last tick: the run ends first.
      if (sample.retreat && r.firstRetreat === null && Number(sample.tick) < summary.ticks) r.firstRetreat = Number(sample.tick);
    }
  } else if (channel.topic === `${prefix}/arena_telemetry`) {
    telemetry += 1;
    const tick = Number(sample.tick);
    telemetryTicks.push(tick);
    const row = telemetryRows.get(tick);
    lastTelemetryTick = Math.max(lastTelemetryTick, tick);
    if (tick === 0) continue;  // telemetry.csv starts at tick 1
    check(row !== undefined, `telemetry of tick ${tick}: no such row in telemetry.csv`);
    if (row === undefined) continue;
    for (const key of ["inside", "waiting", "retreating", "departed", "deliveries"]) {
      check(Number(sample[key]) === Number(row[key]), `telemetry of tick ${tick}: ${key} ${sample[key]}, csv ${row[key]}`);
    }
    check(Math.abs(sample.true_density - Number(row.true_density)) <= 1e-5 * Math.max(1, sample.true_density),
          `telemetry of tick ${tick}: true_density ${sample.true_density}, csv ${row.true_density}`);
  } else if (channel.topic === `${prefix}/poses`) {
    poses += 1;
    posesTicks.push(Number(sample.tick));
    posesByTick.set(Number(sample.tick), sample.robots.map((r) => `${r.robot_id} ${r.x} ${r.y}`).join(";"));
  } else if (channel.topic === `${prefix}/agent_status`) {
    robot(sample.robot_id).lastStatus = sample;
  } else {
    check(false, `unexpected channel ${channel.topic}`);
  }
}
check(messages === Number(reader.statistics.messageCount), `read ${messages} of ${reader.statistics.messageCount} messages`);
check(telemetry > 0 && poses > 0, `${telemetry} telemetry and ${poses} poses samples`);
check(lastTelemetryTick === summary.ticks, `last telemetry tick ${lastTelemetryTick}, the run's ${summary.ticks}`);
// The ticks the arena publishes observations at (arena/program/arena_node.cpp,
// publish_observations): tick 0, then each tick whose time enters a new telemetry period.
const period = JSON.parse(run?.get("config") ?? "{}").run?.telemetry_period;
check(typeof period === "number" && period > 0, `metadata config: run.telemetry_period ${period}`);
const expectedTicks = [0];
let lastSlot = 0;
for (const [tick, row] of [...telemetryRows].sort((a, b) => a[0] - b[0])) {
  const slot = Math.floor(Number(row.time) / period + 1e-9);
  if (slot !== lastSlot) expectedTicks.push(tick);
  lastSlot = slot;
}
const same = (a, b) => a.length === b.length && a.every((x, i) => x === b[i]);
check(same(telemetryTicks, expectedTicks),
      `telemetry at ${telemetryTicks.length} ticks, the arena publishes at ${expectedTicks.length}`);
check(same(posesTicks, expectedTicks), `poses at ${posesTicks.length} ticks, the arena publishes at ${expectedTicks.length}`);

check(sceneByTick.size === posesByTick.size, `${sceneByTick.size} scene updates for ${posesByTick.size} poses samples`);
for (const [tick, drawn] of posesByTick) {
  check(sceneByTick.get(tick) === drawn, `the scene of tick ${tick} does not draw the robots of its poses sample`);
}

let answers = 0, waitedFor = 0, answered = 0;
for (const [id, a] of agents) {
  const r = robot(id);
  answers += r.answers;
  waitedFor += r.answers - r.departedFrames;
  answered += [...r.answerTimes].filter((t) => !r.departedTimes.has(t)).length;
  if (a.agent_matched !== "1") continue;
  check(r.frames > 0, `robot ${id}: no frame recorded`);
  for (const t of r.frameTimes) check(r.answerTimes.has(t), `robot ${id}: the frame of time ${t} has no answer`);
  for (const t of r.answerTimes) check(r.frameTimes.has(t), `robot ${id}: an answer to time ${t}, but no such frame`);
  check(r.onsets === Number(a.onsets), `robot ${id}: ${r.onsets} onsets on its frames, agents.csv ${a.onsets}`);
  const retreatTick = retreats.get(id) ?? null;
  check(r.firstRetreat === retreatTick, `robot ${id}: first retreating answer at ${r.firstRetreat}, retreats.csv ${retreatTick}`);
  check(r.lastStatus !== null, `robot ${id}: no status recorded`);
  if (r.lastStatus !== null) {
    check(r.lastStatus.retreating === (a.retreated === "1"),
          `robot ${id}: last status retreating ${r.lastStatus.retreating}, agents.csv retreated ${a.retreated}`);
  }
}
check(answered <= summary.decisions_received && summary.decisions_received <= waitedFor,
      `${answered} frames answered and ${waitedFor} answers recorded (besides departed frames), ` +
      `but the arena received ${summary.decisions_received}`);

// Streamed, record by record, with the chunks' CRCs checked.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
let streamed = 0;
for (let record; (record = stream.nextRecord()) !== undefined;) streamed += record.type === "Message" ? 1 : 0;
check(stream.done() && streamed === messages, `stream: ${streamed} messages, done ${stream.done()}`);

if (failures > 0) {
  console.error(`check_recording: ${failures} mismatches`);
  process.exit(1);
}
console.log(`check_recording: ok, ${messages} messages on ${reader.channelsById.size} channels, ` +
            `${robots.size} robots, ${telemetry} telemetry samples, ${answers} answers, ` +
            `${sceneByTick.size} valid scene updates: as in ${runDir}`);
