// Decodes recordings and the live feed as the Foxglove app does, with Foxglove's own libraries:
// @mcap/core reads the file (its zstd/lz4 chunks through @mcap/support's decompressors, the
// app's), @foxglove/ws-protocol is the live feed's client, @foxglove/rosmsg parses each
// `ros2msg` schema and @foxglove/rosmsg2-serialization reads the CDR.
//
//   node foxglove_decode.mjs mcap FILE
//   node foxglove_decode.mjs live ws://HOST:PORT SECONDS
//
// Prints one line per topic: `topic<TAB>schema<TAB>messages<TAB>last message as JSON`, then
// `decoded N` (all messages) and exits 0 (a recording first prints `chunks C`: the compressions
// of its chunks, e.g. `zstd`); a schema that does not parse or a message that does not decode
// is a line `error ...` and exit 1.

import { readFileSync } from "node:fs";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import wsProtocol from "@foxglove/ws-protocol";
import WebSocket from "ws";

const { FoxgloveClient } = wsProtocol;

const topics = new Map(); // topic -> { schema, count, last }
const errors = [];
let decoded = 0;

function readerFor(schemaName, encoding, text) {
  if (encoding !== "ros2msg") throw new Error(`schema encoding '${encoding}'`);
  return new MessageReader(parse(text, { ros2: true }));
}

function take(topic, schemaName, reader, bytes) {
  const t = topics.get(topic) ?? { schema: schemaName, count: 0, last: null };
  topics.set(topic, t);
  try {
    t.last = reader.readMessage(bytes);
    t.count++;
    decoded++;
  } catch (e) {
    errors.push(`${topic} (${schemaName}): ${e.message}`);
  }
}

function report() {
  const json = (v) =>
    JSON.stringify(v, (_k, x) =>
      typeof x === "bigint" ? Number(x) : ArrayBuffer.isView(x) ? Array.from(x) : x,
    );
  for (const [topic, t] of [...topics].sort()) {
    console.log(`${topic}\t${t.schema}\t${t.count}\t${json(t.last)}`);
  }
  console.log(`decoded ${decoded}`);
  for (const e of errors.slice(0, 20)) console.log(`error ${e}`);
  process.exit(errors.length ? 1 : 0);
}

const compressions = new Set(); // of the recording's chunks ("(none)": uncompressed)

async function mcap(file) {
  const reader = new McapStreamReader({ decompressHandlers: await loadDecompressHandlers() });
  reader.append(new Uint8Array(readFileSync(file)));
  const schemas = new Map();
  const channels = new Map();
  for (let r; (r = reader.nextRecord()); ) {
    if (r.type === "Schema") {
      schemas.set(r.id, r);
    } else if (r.type === "Channel") {
      const s = schemas.get(r.schemaId);
      try {
        const text = new TextDecoder().decode(s.data);
        channels.set(r.id, { topic: r.topic, schema: s.name, reader: readerFor(s.name, s.encoding, text) });
      } catch (e) {
        errors.push(`${r.topic} (${s?.name}): schema: ${e.message}`);
      }
    } else if (r.type === "Message") {
      const c = channels.get(r.channelId);
      if (c) take(c.topic, c.schema, c.reader, r.data);
    } else if (r.type === "ChunkIndex") {
      compressions.add(r.compression || "(none)");
    }
  }
  if (!reader.done()) errors.push("the file does not end with a valid footer");
  console.log(`chunks ${[...compressions].sort().join(" ")}`);
  report();
}

function live(url, seconds) {
  const client = new FoxgloveClient({
    ws: new WebSocket(url, [FoxgloveClient.SUPPORTED_SUBPROTOCOL]),
  });
  const subs = new Map();
  client.on("error", (e) => {
    errors.push(`connection: ${e.message ?? e}`);
    report();
  });
  client.on("advertise", (channels) => {
    for (const ch of channels) {
      try {
        if (ch.encoding !== "cdr") throw new Error(`message encoding '${ch.encoding}'`);
        const reader = readerFor(ch.schemaName, ch.schemaEncoding ?? "ros2msg", ch.schema);
        const id = client.subscribe(ch.id);
        subs.set(id, { topic: ch.topic, schema: ch.schemaName, reader });
      } catch (e) {
        errors.push(`${ch.topic} (${ch.schemaName}): schema: ${e.message}`);
      }
    }
  });
  client.on("message", ({ subscriptionId, data }) => {
    const s = subs.get(subscriptionId);
    if (s) take(s.topic, s.schema, s.reader, data);
  });
  setTimeout(() => {
    client.close();
    report();
  }, seconds * 1000);
}

const [mode, arg, seconds] = process.argv.slice(2);
if (mode === "mcap" && arg) mcap(arg);
else if (mode === "live" && arg) live(arg, Number(seconds ?? 3));
else {
  console.error("usage: foxglove_decode.mjs mcap FILE | live ws://HOST:PORT SECONDS");
  process.exit(2);
}
