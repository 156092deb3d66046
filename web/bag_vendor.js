// The ROS 1 bag reader the page uses (@foxglove/rosbag: records, chunks, indexes; message
// definitions parsed by @foxglove/rosmsg and messages by @foxglove/rosmsg-serialization), bundled
// into page/vendor/rosbag.js by esbuild: the page's only third-party code, and no build step for
// the page itself.
export { Bag } from "@foxglove/rosbag";
export { MessageReader } from "@foxglove/rosmsg-serialization";
export { parse as parseMessageDefinition } from "@foxglove/rosmsg";
