#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// Independent reader of sonarsynth's ROS 2 bags (docs/robotics.md): @mcap/core reads the MCAP
// container (the summary, its CRC, the chunk index, each chunk's CRC and zstd data), the
// data-section CRC is checked here, every message is decoded with the schema embedded in the
// file (@foxglove/rosmsg parses the ros2msg text, @foxglove/rosmsg2-serialization reads the
// CDR). Prints one JSON object on stdout; exits 1 with a message on any inconsistency.
// Usage: node read_bag.js FILE.mcap
"use strict";
const fs = require("fs");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const { crc32 } = require("@foxglove/crc");
const zstd = require("@foxglove/wasm-zstd");

function fail(message) {
  process.stderr.write(`read_bag: ${message}\n`);
  process.exit(1);
}

const MAGIC = [0x89, 0x4d, 0x43, 0x41, 0x50, 0x30, 0x0d, 0x0a];

function samplesOf(image) {
  const d = image.data;
  const view = new DataView(d.buffer, d.byteOffset, d.byteLength);
  const out = [];
  if (image.is_bigendian) fail("image.is_bigendian is true");
  if (image.dtype === 2) for (let i = 0; i < d.byteLength; i += 2) out.push(view.getUint16(i, true));
  else if (image.dtype === 0) for (let i = 0; i < d.byteLength; i++) out.push(d[i]);
  else if (image.dtype === 8) for (let i = 0; i < d.byteLength; i += 4) out.push(view.getFloat32(i, true));
  else fail(`unexpected dtype ${image.dtype}`);
  return out;
}

async function main() {
  const path = process.argv[2];
  if (!path) fail("usage: node read_bag.js FILE.mcap");
  const bytes = new Uint8Array(fs.readFileSync(path));
  await zstd.isLoaded;
  const decompressHandlers = {
    zstd: (buffer, size) => zstd.decompress(buffer, Number(size)),
  };
  for (let i = 0; i < 8; i++) {
    if (bytes[i] !== MAGIC[i] || bytes[bytes.length - 8 + i] !== MAGIC[i]) fail("bad magic");
  }
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  // Summary (its CRC is checked by Initialize), statistics, chunk indexes.
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  if (reader.header.profile !== "ros2") fail(`profile ${reader.header.profile}`);
  // Data section CRC: every byte before the DataEnd record (13 bytes before the summary).
  const summaryStart = Number(reader.footer.summaryStart);
  const dataEnd = summaryStart - 13;
  if (bytes[dataEnd] !== 0x0f) fail("no DataEnd record right before the summary");
  const stored = new DataView(bytes.buffer).getUint32(dataEnd + 9, true);
  const computed = crc32(bytes.subarray(0, dataEnd));
  if (stored !== computed) fail(`data section CRC ${computed} != stored ${stored}`);

  const decoders = new Map();
  for (const [id, channel] of reader.channelsById) {
    const schema = reader.schemasById.get(channel.schemaId);
    if (!schema || schema.encoding !== "ros2msg" || channel.messageEncoding !== "cdr") {
      fail(`channel ${channel.topic}: schema ${schema && schema.encoding}, ${channel.messageEncoding}`);
    }
    const text = new TextDecoder().decode(schema.data);
    decoders.set(id, { topic: channel.topic, type: schema.name, reader: new MessageReader(parse(text, { ros2: true })) });
  }
  const out = { profile: reader.header.profile, schemas: reader.schemasById.size, types: {}, chunks: reader.chunkIndexes.length, compression: [], topics: {}, messages: 0, pings: [], nav: [], imu: [], tf: [], truth: [] };
  for (const d of [...decoders.values()].sort((a, b) => (a.topic < b.topic ? -1 : 1))) out.types[d.topic] = d.type;
  out.compression = [...new Set(reader.chunkIndexes.map((c) => c.compression))];
  const port = new Map();
  // readMessages checks each chunk's CRC and uses the message indexes (log-time order).
  for await (const m of reader.readMessages()) {
    const d = decoders.get(m.channelId);
    const msg = d.reader.readMessage(m.data);
    out.messages++;
    out.topics[d.topic] = (out.topics[d.topic] || 0) + 1;
    const stampNs = BigInt(msg.header ? msg.header.stamp.sec : 0) * 1000000000n + BigInt(msg.header ? msg.header.stamp.nanosec : 0);
    if (msg.header && stampNs !== m.logTime) fail(`${d.topic}: header stamp ${stampNs} != log time ${m.logTime}`);
    const t = Number(m.logTime / 1000n);  // microseconds
    if (d.type === "marine_acoustic_msgs/msg/RawSonarImage") {
      const side = { t_us: t, frame_id: msg.header.frame_id, sample_rate: msg.sample_rate, samples_per_beam: msg.samples_per_beam, sound_speed: msg.ping_info.sound_speed, frequency: msg.ping_info.frequency, samples: samplesOf(msg.image) };
      if (side.samples.length !== msg.samples_per_beam || msg.image.beam_count !== 1) fail(`${d.topic}: ${side.samples.length} samples, samples_per_beam ${msg.samples_per_beam}`);
      if (d.topic.endsWith("/port")) port.set(t, side);
      else out.pings.push({ t_us: t, port: port.get(t), starboard: side });
    } else if (d.type === "sensor_msgs/msg/NavSatFix") {
      out.nav.push({ t_us: t, lat_deg: msg.latitude, lon_deg: msg.longitude, frame_id: msg.header.frame_id });
    } else if (d.type === "sensor_msgs/msg/Imu") {
      out.imu.push({ t_us: t, q: [msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w] });
    } else if (d.type === "sonarsynth_msgs/msg/SideScanTruth") {
      // Typed arrays as plain arrays; NaN prints as null.
      out.truth.push({ topic: d.topic, t_us: t, frame_id: msg.header.frame_id, samples: msg.samples, sample_class: Array.from(msg.sample_class), label: Array.from(msg.label), grazing_rad: Array.from(msg.grazing_rad), ground_range_m: Array.from(msg.ground_range_m) });
    } else if (d.type === "tf2_msgs/msg/TFMessage") {
      for (const tr of msg.transforms) out.tf.push({ parent: tr.header.frame_id, child: tr.child_frame_id, rotation: tr.transform.rotation });
    }
  }
  // Per ping (time) port then starboard.
  const sideOf = (m) => (m.topic.endsWith("/starboard/truth") ? 1 : 0);
  out.truth.sort((a, b) => a.t_us - b.t_us || sideOf(a) - sideOf(b));
  const stats = reader.statistics;
  if (!stats || Number(stats.messageCount) !== out.messages) fail(`statistics say ${stats && stats.messageCount} messages, read ${out.messages}`);
  for (const [id, n] of stats.channelMessageCounts) {
    if (Number(n) !== (out.topics[decoders.get(id).topic] || 0)) fail(`channel ${id}: statistics ${n}`);
  }
  // The same file read front to back, record by record (chunk CRCs checked again).
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  let streamed = 0, record, ended = false;
  while ((record = stream.nextRecord())) {
    if (record.type === "Message") streamed++;
    if (record.type === "Footer") ended = true;
  }
  if (!ended || !stream.done()) fail("stream reader did not reach the footer");
  if (streamed !== out.messages) fail(`stream reader read ${streamed} messages, indexed ${out.messages}`);
  process.stdout.write(JSON.stringify(out) + "\n");
}

main().catch((e) => fail(e && e.stack ? e.stack : String(e)));
