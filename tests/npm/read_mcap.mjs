// An MCAP file read by the MCAP project's own reader (@mcap/core, indexed: summary,
// chunk indexes, message indexes, CRCs) and its ROS 2 messages decoded by Foxglove's
// (@foxglove/rosmsg2-serialization, the schemas parsed by @foxglove/rosmsg): what
// Foxglove itself does with a file. Prints JSON: the header, every channel (schema,
// encodings, the count the statistics give and the count read) and each topic's
// first message decoded (arrays longer than 64 summarised: length, sum, -1s).
//   node read_mcap.mjs FILE.mcap
import { McapIndexedReader } from "@mcap/core";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg2-serialization";
import { decompress } from "fzstd";
import { open } from "node:fs/promises";

const file = await open(process.argv[2], "r");
const size = BigInt((await file.stat()).size);
const readable = {
  size: async () => size,
  read: async (offset, length) => {
    const buffer = Buffer.alloc(Number(length));
    await file.read(buffer, 0, Number(length), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({
  readable,
  decompressHandlers: { zstd: (data, decompressedSize) => decompress(data, new Uint8Array(Number(decompressedSize))) },
});
const out = { profile: reader.header.profile, library: reader.header.library, channels: {}, first: {} };
const decoders = new Map();
for (const [id, channel] of reader.channelsById) {
  const schema = reader.schemasById.get(channel.schemaId);
  out.channels[channel.topic] = {
    schema: schema.name,
    schemaEncoding: schema.encoding,
    messageEncoding: channel.messageEncoding,
    statistics: Number(reader.statistics?.channelMessageCounts.get(id) ?? -1n),
    read: 0,
  };
  decoders.set(id, new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })));
}
for await (const message of reader.readMessages({ validateCrcs: true })) {
  const topic = reader.channelsById.get(message.channelId).topic;
  out.channels[topic].read++;
  if (!(topic in out.first)) out.first[topic] = decoders.get(message.channelId).readMessage(message.data);
}
await file.close();
const summarise = (key, value) => {
  if (typeof value === "bigint") return Number(value);
  if (typeof value === "number" && !Number.isFinite(value)) return String(value);
  if (!ArrayBuffer.isView(value) && !Array.isArray(value)) return value;
  const list = Array.from(value);
  if (list.length > 0 && typeof list[0] === "object") return list.length <= 64 ? list : { length: list.length, first: list[0] };
  if (list.length <= 64) return list;
  const finite = list.filter((v) => Number.isFinite(v));
  return {
    length: list.length,
    finite_sum: finite.reduce((a, b) => a + b, 0),
    non_finite: list.length - finite.length,
    minus_one: list.filter((v) => v === -1).length,
  };
};
console.log(JSON.stringify(out, summarise));
