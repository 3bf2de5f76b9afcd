/// Snapshot decode bench: the C++ decoder (proto/snapshot_codec.h) on a recorded snapshot stream,
/// tests/vectors/snapshots_*.txt (one client's stream of snapshot-bench's spheres901 or players64
/// scene, losses included), so that the Java client's decoder can be timed on the very same bytes
/// in the same run (tools/bench/java_decode.sh; the Java side is
/// tools/bench/java/io/ricochet/bench/SnapshotDecodeBench.java, which prints the same fields).
///
/// The stream is decoded round after round by one decoder, each round's ticks moved on by 2^20 (a
/// multiple of the baseline ring, so every delta finds its baseline as in the recording); the
/// warm-up rounds are not measured. Each decode of a parsed wire::Snapshot is timed on the steady
/// clock (the message parse is not: the Java side decodes the entity bytes, parsed once, too);
/// per-snapshot figures are nearest rank (ricochet/stats). cpu_us_per_snapshot is the thread's
/// CPU time over the measured rounds per snapshot: steadier than wall time on a shared machine.
///
///   snapshot-decode-bench --vectors FILE [--rounds 200] [--warmup-rounds 100] [--out FILE]

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "harness.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/proto/snapshot_codec.h"

namespace proto = ricochet::proto;
namespace bench = ricochet::bench;
namespace stats = ricochet::stats;

namespace {

constexpr std::uint32_t kRoundTicks = 1u << 20;

/// The records of a vector file this bench needs: the spec and the received snapshots.
struct Stream {
  std::string scene;
  std::uint64_t entities = 0;
  proto::QuantizationSpec spec;
  std::vector<ricochet::wire::Snapshot> snapshots;
};

/// The value of `key=` in a record line; empty when absent.
std::string_view field(std::string_view line, std::string_view key) {
  std::size_t at = 0;
  while ((at = line.find(key, at)) != std::string_view::npos) {
    if ((at == 0 || line[at - 1] == ' ') && line.size() > at + key.size() &&
        line[at + key.size()] == '=') {
      const std::size_t start = at + key.size() + 1;
      const std::size_t end = line.find(' ', start);
      return line.substr(start, end == std::string_view::npos ? line.size() - start : end - start);
    }
    at += key.size();
  }
  return {};
}

std::optional<std::string> from_hex(std::string_view hex) {
  if (hex.size() % 2 != 0) return std::nullopt;
  std::string bytes(hex.size() / 2, '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    unsigned value = 0;
    for (char c : hex.substr(2 * i, 2)) {
      value <<= 4;
      if (c >= '0' && c <= '9') {
        value |= static_cast<unsigned>(c - '0');
      } else if (c >= 'a' && c <= 'f') {
        value |= static_cast<unsigned>(c - 'a' + 10);
      } else {
        return std::nullopt;
      }
    }
    bytes[i] = static_cast<char>(value);
  }
  return bytes;
}

/// Reads `path`; an empty error when it holds a spec and at least one snapshot.
std::string read_stream(const std::string& path, Stream& out) {
  std::ifstream in(path);
  if (!in) return "cannot read " + path;
  std::string line;
  bool have_spec = false;
  while (std::getline(in, line)) {
    const std::string_view view(line);
    const bool spec = view.starts_with("spec ");
    if (!spec && !view.starts_with("snapshot ")) continue;
    const std::optional<std::string> bytes = from_hex(field(view, "bytes"));
    if (!bytes) return path + ": bad hex in " + line.substr(0, 40);
    if (spec) {
      ricochet::wire::Quantization wire;
      if (!wire.ParseFromString(*bytes)) return path + ": the spec does not parse";
      std::string error;
      const std::optional<proto::QuantizationSpec> parsed = proto::from_wire(wire, error);
      if (!parsed) return path + ": " + error;
      out.spec = *parsed;
      out.scene = std::string(field(view, "scene"));
      out.entities = std::stoull(std::string(field(view, "entities")));
      have_spec = true;
    } else {
      ricochet::wire::Snapshot& snapshot = out.snapshots.emplace_back();
      if (!snapshot.ParseFromString(*bytes)) return path + ": a snapshot does not parse";
    }
  }
  if (!have_spec || out.snapshots.empty()) return path + ": no spec or no snapshot";
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Snapshot decode bench: the C++ decoder on a recorded stream (tests/vectors)");
  std::string vectors, out;
  int rounds = 200, warmup_rounds = 100;
  app.add_option("--vectors", vectors, "tests/vectors/snapshots_*.txt")->required();
  app.add_option("--rounds", rounds, "measured rounds of the stream")->check(CLI::Range(1, 3000));
  app.add_option("--warmup-rounds", warmup_rounds, "rounds before measuring")
      ->check(CLI::Range(0, 1000));
  app.add_option("--out", out, "also append the JSON line to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "snapshot-decode-bench: cannot write %s\n", out.c_str());
    return 1;
  }
  Stream stream;
  if (const std::string error = read_stream(vectors, stream); !error.empty()) {
    std::fprintf(stderr, "snapshot-decode-bench: %s\n", error.c_str());
    return 1;
  }

  std::vector<std::uint32_t> ticks;
  for (const ricochet::wire::Snapshot& s : stream.snapshots) ticks.push_back(s.tick());
  proto::SnapshotDecoder decoder(stream.spec);
  std::vector<double> samples_us;
  samples_us.reserve(static_cast<std::size_t>(rounds) * stream.snapshots.size());
  std::uint64_t refused = 0;
  std::int64_t cpu_ns = 0;
  double wall_us = 0;
  for (int round = 0; round < warmup_rounds + rounds; ++round) {
    const bool measured = round >= warmup_rounds;
    const std::uint32_t offset = static_cast<std::uint32_t>(round) * kRoundTicks;
    for (std::size_t i = 0; i < ticks.size(); ++i) stream.snapshots[i].set_tick(ticks[i] + offset);
    const std::int64_t cpu_start = bench::thread_cpu_ns();
    for (const ricochet::wire::Snapshot& snapshot : stream.snapshots) {
      bench::Stopwatch watch;
      const bool ok = decoder.decode(snapshot).ok;
      const double us = watch.elapsed_us();
      refused += !ok;
      if (measured) {
        samples_us.push_back(us);
        wall_us += us;
      }
    }
    if (measured) cpu_ns += bench::thread_cpu_ns() - cpu_start;
  }
  const double snapshots = static_cast<double>(samples_us.size());
  const stats::Summary summary = stats::summarize(samples_us);
  results.write(bench::result_line("snapshot_decode")
                    .text("lang", "cpp")
                    .text("scene", stream.scene)
                    .integer("entities", stream.entities)
                    .integer("stream_snapshots", stream.snapshots.size())
                    .integer("rounds", rounds)
                    .integer("warmup_rounds", warmup_rounds)
                    .number("decode_us", wall_us / snapshots, 3)
                    .number("decode_us_p50", summary.p50, 3)
                    .number("decode_us_p99", summary.p99, 3)
                    .number("decode_us_min", summary.min, 3)
                    .number("cpu_us_per_snapshot", static_cast<double>(cpu_ns) / 1e3 / snapshots, 3)
                    .integer("refused", refused));
  return refused == 0 ? 0 : 1;
}
