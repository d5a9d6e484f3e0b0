// ROS 2 messages serialized by Foxglove's CDR writer (@foxglove/rosmsg2-serialization,
// the definitions parsed by @foxglove/rosmsg): the bytes a ROS 2 tool writes for the
// same values, to compare with what specht publishes over DDS and records in MCAP.
// Input: a JSON list of {type, definition, value}; times are {sec, nsec}. Output: a
// JSON list of {type, hex}.
//   node write_cdr.mjs CASES.json
import { parse } from "@foxglove/rosmsg";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import { readFileSync } from "node:fs";

const cases = JSON.parse(readFileSync(process.argv[2], "utf8"));
const out = cases.map(({ type, definition, value }) => {
  const writer = new MessageWriter(parse(definition, { ros2: true }));
  return { type, hex: Buffer.from(writer.writeMessage(value)).toString("hex") };
});
process.stdout.write(JSON.stringify(out));
