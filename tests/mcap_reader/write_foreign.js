#!/usr/bin/env node
// SPDX-License-Identifier: MIT
// An MCAP bag of "another robot" written by independent code, for sonarsynth's reader
// (docs/robotics.md, "Reading bags"): @mcap/core's McapWriter writes the container and
// @foxglove/rosmsg2-serialization the CDR, from the ros2msg definitions embedded in a sonarsynth
// bag. Topics and frames are not sonarsynth's: one /robot/sss/raw topic carries both sides
// (frames sss_port and sss_stbd), /robot/gps/fix the NavSatFix, /robot/imu/data the Imu, and a
// JSON channel without schema is there to be ignored. Per ping k (0..5), 250 samples per side:
// sample i of side s (0 port, 1 starboard) = (1009 k + 37 i + 5000 s) mod 32768 (uint16);
// stamp 1700000000.12 s + 0.25 k; latitude 47.25 + 1e-5 k, longitude -122.5; heading 30 + k
// degrees; sound speed 1480 m/s; slant range 30 m.
// Usage: node write_foreign.js SONARSYNTH.mcap OUT.mcap MODE
//   MODE indexed:   uncompressed chunks of ~2 kB, chunk and message indexes, statistics
//   MODE unchunked: messages outside chunks, a summary without chunk indexes
//   MODE nosummary: zstd chunks, no summary at all (footer summary_start = 0)
"use strict";
const fs = require("fs");
const { McapIndexedReader, McapWriter, TempBuffer } = require("@mcap/core");
const { parse } = require("@foxglove/rosmsg");
const { MessageWriter } = require("@foxglove/rosmsg2-serialization");
const zstd = require("@foxglove/wasm-zstd");

async function main() {
  const [source, out, mode] = process.argv.slice(2);
  if (!["indexed", "unchunked", "nosummary"].includes(mode)) {
    throw new Error("usage: node write_foreign.js SONARSYNTH.mcap OUT.mcap indexed|unchunked|nosummary");
  }
  await zstd.isLoaded;
  const bytes = new Uint8Array(fs.readFileSync(source));
  const readable = {
    size: async () => BigInt(bytes.length),
    read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
  };
  const reader = await McapIndexedReader.Initialize({ readable });
  const schemas = new Map();
  for (const s of reader.schemasById.values()) schemas.set(s.name, s);

  const buffer = new TempBuffer();
  const options = { writable: buffer, chunkSize: 2000 };
  if (mode === "unchunked") options.useChunks = false;
  if (mode === "nosummary") {
    Object.assign(options, { useStatistics: false, useSummaryOffsets: false, useChunkIndex: false,
      repeatSchemas: false, repeatChannels: false, useMessageIndex: false,
      compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data) }) });
  }
  const writer = new McapWriter(options);
  await writer.start({ profile: "ros2", library: "write_foreign.js" });
  const channels = {};
  const serializers = {};
  const add = async (topic, type) => {
    const s = schemas.get(type);
    const schemaId = await writer.registerSchema({ name: s.name, encoding: s.encoding, data: s.data });
    channels[topic] = await writer.registerChannel({ topic, schemaId, messageEncoding: "cdr", metadata: new Map() });
    serializers[topic] = new MessageWriter(parse(new TextDecoder().decode(s.data), { ros2: true }));
  };
  await add("/robot/gps/fix", "sensor_msgs/msg/NavSatFix");
  await add("/robot/imu/data", "sensor_msgs/msg/Imu");
  await add("/robot/sss/raw", "marine_acoustic_msgs/msg/RawSonarImage");
  const status = await writer.registerChannel({ topic: "/robot/status", schemaId: 0, messageEncoding: "json", metadata: new Map() });

  const n = 250;
  let sequence = 0;
  const put = async (topic, channelId, stamp, data) => {
    const t = BigInt(stamp.sec) * 1000000000n + BigInt(stamp.nanosec);
    await writer.addMessage({ channelId, sequence: sequence++, logTime: t, publishTime: t, data });
  };
  const cdr = (topic, msg) => serializers[topic].writeMessage(msg);
  const zero9 = new Array(9).fill(0);
  for (let k = 0; k < 6; k++) {
    const ns = 120000000 + 250000000 * k;
    const stamp = { sec: 1700000000 + Math.floor(ns / 1e9), nanosec: ns % 1e9 };
    const header = (frame_id) => ({ stamp, frame_id });
    await put("/robot/status", status, stamp, new TextEncoder().encode(JSON.stringify({ ping: k })));
    await put("/robot/gps/fix", channels["/robot/gps/fix"], stamp, cdr("/robot/gps/fix", {
      header: header("gps"), status: { status: 0, service: 1 }, latitude: 47.25 + 1e-5 * k,
      longitude: -122.5, altitude: NaN, position_covariance: zero9, position_covariance_type: 0 }));
    const yaw = Math.PI / 2 - (30 + k) * Math.PI / 180;  // ENU yaw of heading 30 + k degrees
    const v3 = { x: 0, y: 0, z: 0 };
    await put("/robot/imu/data", channels["/robot/imu/data"], stamp, cdr("/robot/imu/data", {
      header: header("imu_link"), orientation: { x: 0, y: 0, z: Math.sin(yaw / 2), w: Math.cos(yaw / 2) },
      orientation_covariance: zero9, angular_velocity: v3, angular_velocity_covariance: zero9,
      linear_acceleration: v3, linear_acceleration_covariance: zero9 }));
    for (const [side, frame] of [[0, "sss_port"], [1, "sss_stbd"]]) {
      const data = new Uint8Array(2 * n);
      for (let i = 0; i < n; i++) {
        const v = (1009 * k + 37 * i + 5000 * side) % 32768;
        data[2 * i] = v & 0xff;
        data[2 * i + 1] = v >> 8;
      }
      await put("/robot/sss/raw", channels["/robot/sss/raw"], stamp, cdr("/robot/sss/raw", {
        header: header(frame),
        ping_info: { frequency: 900e3, sound_speed: 1480, tx_beamwidths: [0.01], rx_beamwidths: [0.8] },
        sample_rate: n * 1480 / (2 * 30), samples_per_beam: n, sample0: 0,
        tx_delays: [0], tx_angles: [0], rx_angles: [0],
        image: { is_bigendian: false, dtype: 2, beam_count: 1, data } }));
    }
  }
  await writer.end();
  fs.writeFileSync(out, buffer.get());
}

main().catch((e) => {
  process.stderr.write(`write_foreign: ${e && e.stack ? e.stack : String(e)}\n`);
  process.exit(1);
});
