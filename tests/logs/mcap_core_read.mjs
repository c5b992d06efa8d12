// Reads MCAP files with the official TypeScript reader, @mcap/core's McapIndexedReader
// (the one Foxglove is built on), and prints what it found as JSON on stdout.
//
//   node mcap_core_read.mjs NODE_PREFIX FILE.mcap...
//
// NODE_PREFIX is the folder whose node_modules hold @mcap/core, @mcap/support (the
// zstd/lz4/bz2 decompressors, protobuf descriptors) and @mcap/nodejs; the tests install
// them there (tests/logs/node_reader.py). Chunk CRCs are checked while reading messages
// and the summary CRC when the reader opens the file. Per file: the header, channels and
// schemas, the statistics, the messages counted per topic, the metadata records, the
// chunk indexes (compression, message index offsets), the /foxglove/scene messages
// decoded with the protobuf schema stored in the file, and the .npy headers of the
// /srfm/trajectories arrays.
import { createRequire } from "node:module";
import { open } from "node:fs/promises";
import path from "node:path";

const [prefix, ...files] = process.argv.slice(2);
const require = createRequire(path.join(path.resolve(prefix), "index.js"));
const { McapIndexedReader } = require("@mcap/core");
const { loadDecompressHandlers, protobufFromBinaryDescriptor } = require("@mcap/support");
const { FileHandleReadable } = require("@mcap/nodejs");

const decompressHandlers = await loadDecompressHandlers();
const textDecoder = new TextDecoder();

function npyHeader(base64) {
  const raw = Buffer.from(base64, "base64");
  const magic = raw.subarray(0, 6).toString("latin1");
  if (magic !== "\x93NUMPY") {
    throw new Error(`not a .npy file (magic ${JSON.stringify(magic)})`);
  }
  const headerLength = raw.readUInt16LE(8);
  const header = raw.subarray(10, 10 + headerLength).toString("latin1");
  const descr = /'descr':\s*'([^']+)'/.exec(header)[1];
  const shapeText = /'shape':\s*\(([^)]*)\)/.exec(header)[1];
  const shape = shapeText
    .split(",")
    .map((s) => s.trim())
    .filter((s) => s.length > 0)
    .map(Number);
  const itemSize = Number(/\d+$/.exec(descr)[0]);
  const count = shape.reduce((a, b) => a * b, 1);
  return { descr, shape, dataBytes: raw.length - 10 - headerLength, expectedBytes: count * itemSize };
}

const num = (v) => (typeof v === "number" ? v : Number(v ?? 0));
const xy = (pose) => [num(pose?.position?.x), num(pose?.position?.y)];

function sceneSummary(update) {
  return (update.entities ?? []).map((e) => ({
    id: e.id,
    frameId: e.frame_id ?? e.frameId,
    timestamp: [num(e.timestamp?.seconds ?? e.timestamp?.sec), num(e.timestamp?.nanos ?? e.timestamp?.nsec)],
    cylinders: (e.cylinders ?? []).map((c) => [...xy(c.pose), num(c.size?.x), num(c.color?.a)]),
    arrows: (e.arrows ?? []).map((a) => [
      ...xy(a.pose),
      num(a.pose?.orientation?.z),
      num(a.pose?.orientation?.w),
      num(a.shaft_length ?? a.shaftLength),
    ]),
    lines: (e.lines ?? []).map((l) => ({
      type: num(l.type),
      points: (l.points ?? []).map((p) => [num(p.x), num(p.y)]),
    })),
    texts: (e.texts ?? []).map((t) => t.text),
  }));
}

async function readFile(file) {
  const handle = await open(file, "r");
  try {
    const reader = await McapIndexedReader.Initialize({
      readable: new FileHandleReadable(handle),
      decompressHandlers,
    });
    const channels = {};
    const decoders = {};
    for (const [id, channel] of reader.channelsById) {
      const schema = reader.schemasById.get(channel.schemaId);
      channels[channel.topic] = {
        id,
        messageEncoding: channel.messageEncoding,
        schemaName: schema?.name ?? null,
        schemaEncoding: schema?.encoding ?? null,
      };
      if (schema?.encoding === "protobuf") {
        const type = protobufFromBinaryDescriptor(schema.data).lookupType(schema.name);
        decoders[id] = (data) => type.toObject(type.decode(data), { longs: Number, enums: Number });
      } else if (channel.messageEncoding === "json") {
        decoders[id] = (data) => JSON.parse(textDecoder.decode(data));
      }
    }
    const counts = {};
    const scene = [];
    const arrays = {};
    const planes = {};
    let previous = -1n;
    let ordered = true;
    for await (const message of reader.readMessages()) {
      const topic = reader.channelsById.get(message.channelId).topic;
      counts[topic] = (counts[topic] ?? 0) + 1;
      if (message.logTime < previous) {
        ordered = false;
      }
      previous = message.logTime;
      const decode = decoders[message.channelId];
      const doc = decode ? decode(message.data) : null;
      if (topic === "/foxglove/scene") {
        scene.push({ logTime: Number(message.logTime), entities: sceneSummary(doc) });
      } else if (topic === "/srfm/trajectories") {
        arrays[doc.group] = Object.fromEntries(
          Object.entries(doc.arrays).map(([name, text]) => [name, npyHeader(text)]),
        );
        planes[doc.group] = doc.planes ?? {};
      }
    }
    const metadata = {};
    for await (const record of reader.readMetadata()) {
      metadata[record.name] = Object.fromEntries(record.metadata);
    }
    const stats = reader.statistics;
    const statisticsCounts = {};
    for (const [id, n] of stats?.channelMessageCounts ?? []) {
      statisticsCounts[reader.channelsById.get(id).topic] = Number(n);
    }
    return {
      file,
      ok: true,
      library: reader.header.library,
      channels,
      counts,
      ordered,
      statistics: {
        messageCount: Number(stats?.messageCount ?? -1),
        channelMessageCounts: statisticsCounts,
      },
      chunks: reader.chunkIndexes.map((c) => ({
        compression: c.compression,
        messageIndexes: c.messageIndexOffsets.size,
      })),
      metadata,
      scene,
      arrays,
      planes,
    };
  } catch (error) {
    return { file, ok: false, error: String(error?.message ?? error) };
  } finally {
    await handle.close();
  }
}

const results = [];
for (const file of files) {
  results.push(await readFile(file));
}
process.stdout.write(JSON.stringify(results));
