/// The encoder's output pinned bit for bit: a scripted scene (entities moving, joining and
/// leaving, acknowledgements arriving late, budgets from roomy to tight) hashed over every
/// serialised snapshot and report. The stored hash was taken before the encoder was optimised;
/// a change that alters it changes the wire output, which no speed-up may do. Each tick's fields
/// and stream hash are pinned too, so that a change names the first tick and field it alters;
/// and every tick the client's decoded entities must be the world but for what the budget left
/// out.
///
/// The scene is built from std::mt19937's raw integers only (no distributions, no floats), so
/// the hash is the same on every standard library.

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <iterator>
#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_test_world.h"

namespace ricochet::proto::snapshot_golden_test {
namespace {

class Fnv1a {
 public:
  void add(std::uint64_t value) {
    for (int k = 0; k < 8; ++k) add_byte(static_cast<std::uint8_t>(value >> (8 * k)));
  }
  void add(const std::string& bytes) {
    for (const char c : bytes) add_byte(static_cast<std::uint8_t>(c));
  }
  std::uint64_t value() const { return hash_; }

 private:
  void add_byte(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= 1099511628211ull;
  }
  std::uint64_t hash_ = 14695981039346656037ull;
};

QuantizedEntity scripted_entity(std::uint32_t id, const QuantizationSpec& spec,
                                std::mt19937& random) {
  QuantizedEntity e;
  e.id = id;
  for (int a = 0; a < 3; ++a) {
    e.position[a] = random() % spec.position_steps(a);
    e.velocity[a] = static_cast<std::int32_t>(random() % 2001) - 1000;
  }
  if (random() % 2 == 0) {
    e.orientation_largest = static_cast<std::uint8_t>(random() % 4);
    for (std::int32_t& c : e.orientation) {
      c = static_cast<std::int32_t>(random() % 401) - 200;
    }
  }
  e.flags = random() % 4 == 0 ? static_cast<std::uint8_t>(random()) : 0;
  return e;
}

/// Moves about a third of the entities, sometimes exactly as predicted.
void step_world(std::vector<QuantizedEntity>& world, const QuantizationSpec& spec,
                std::mt19937& random) {
  for (QuantizedEntity& e : world) {
    if (random() % 3 != 0) continue;
    for (int a = 0; a < 3; ++a) {
      const std::int64_t moved =
          static_cast<std::int64_t>(e.position[a]) + static_cast<std::int64_t>(random() % 81) - 40;
      e.position[a] = static_cast<std::uint32_t>(
          std::clamp<std::int64_t>(moved, 0, spec.position_steps(a) - 1));
      if (random() % 4 == 0) e.velocity[a] += static_cast<std::int32_t>(random() % 21) - 10;
    }
    if (random() % 5 == 0 && e.orientation_largest != 3) {
      e.orientation[random() % 3] = static_cast<std::int32_t>(random() % 401) - 200;
    }
    if (random() % 40 == 0) e.flags ^= 2;
  }
}

/// What one tick's snapshot was, field by field, so that a change names the first tick and
/// field that differ (the scene's hash covers the same bytes and numbers).
struct TickFields {
  std::uint32_t baseline_age = 0;  ///< 0: no baseline (report has_baseline false)
  std::uint32_t entities = 0;      ///< report: in the world
  std::uint32_t pending = 0;       ///< report
  std::uint32_t sent = 0;          ///< report (deferred is pending - sent)
  std::uint32_t bytes = 0;         ///< report: the serialised snapshot
  std::uint32_t stream_fnv = 0;    ///< FNV-1a of the entity stream, folded to 32 bits
};

std::uint32_t folded_fnv(const std::string& bytes) {
  Fnv1a hash;
  hash.add(bytes);
  return static_cast<std::uint32_t>(hash.value() ^ (hash.value() >> 32));
}

/// The first field of `got` that differs from `pinned`, named with both values; empty if none.
std::string first_difference(const TickFields& pinned, const TickFields& got) {
  const std::pair<const char*, std::uint32_t TickFields::*> fields[] = {
      {"baseline_age", &TickFields::baseline_age},
      {"report.entities", &TickFields::entities},
      {"report.pending", &TickFields::pending},
      {"report.sent", &TickFields::sent},
      {"report.bytes", &TickFields::bytes},
      {"entity stream (FNV-1a)", &TickFields::stream_fnv}};
  for (const auto& [name, field] : fields) {
    if (pinned.*field != got.*field) {
      return std::string(name) + ": pinned " + std::to_string(pinned.*field) + ", got " +
             std::to_string(got.*field);
    }
  }
  return {};
}

/// How many entities `decoded` holds differently from `world` (both sorted by id): at another
/// state, missing or extra.
std::size_t differing_entities(std::span<const QuantizedEntity> decoded,
                               std::span<const QuantizedEntity> world) {
  std::size_t differing = 0, i = 0, j = 0;
  while (i < world.size() || j < decoded.size()) {
    if (j == decoded.size() || (i < world.size() && world[i].id < decoded[j].id)) {
      ++differing;
      ++i;
    } else if (i == world.size() || decoded[j].id < world[i].id) {
      ++differing;
      ++j;
    } else {
      differing += !(world[i++] == decoded[j++]);
    }
  }
  return differing;
}

struct SceneResult {
  std::uint64_t hash = 0;
  int deferred_snapshots = 0;     ///< the budget left something out
  int delta_snapshots = 0;        ///< encoded against a baseline
  std::vector<TickFields> ticks;  ///< tick 1 first
};

/// Every tick of the scene as the encoder wrote it when the hash was pinned (taken from the same
/// encoder, which the hash shows): baseline_age, entities, pending, sent, bytes, stream FNV.
// clang-format off
constexpr TickFields kPinnedTicks[] = {
    {0, 150, 150, 68, 976, 0x05acf3c5},
    {0, 150, 150, 68, 981, 0x2aa1e31c},
    {2, 151, 122, 83, 986, 0xbf39e1d9},
    {3, 150, 133, 68, 981, 0x2a188cdd},
    {3, 150, 131, 67, 982, 0x89e5385e},
    {4, 150, 136, 70, 990, 0x160e1829},
    {4, 150, 132, 124, 1017, 0x9816f482},
    {5, 150, 136, 119, 1019, 0xec0a1b37},
    {5, 150, 137, 130, 1023, 0xf87b3553},
    {6, 150, 144, 126, 1027, 0xc28ebfe7},
    {6, 150, 144, 126, 1031, 0x7266c861},
    {7, 149, 145, 122, 1025, 0xaef78bba},
    {7, 149, 147, 121, 1027, 0xe9bbce49},
    {8, 149, 148, 119, 1034, 0x3c09a59a},
    {9, 149, 148, 119, 1033, 0x7198cb51},
    {10, 150, 150, 114, 1033, 0xb30eea2d},
    {5, 151, 135, 135, 888, 0xa4dec667},
    {5, 151, 133, 133, 903, 0x00d35b37},
    {6, 152, 141, 141, 998, 0x3df1fdaf},
    {7, 152, 144, 142, 1033, 0xe66b2317},
    {8, 152, 145, 139, 1034, 0x52b356b4},
    {7, 153, 148, 139, 1033, 0xb05eb007},
    {8, 153, 151, 134, 1035, 0x38606ef2},
    {8, 153, 150, 135, 1034, 0x5aca905a},
    {9, 153, 150, 131, 1030, 0xfe1cdfb9},
    {6, 153, 145, 145, 998, 0xf4f86dde},
    {5, 153, 134, 134, 897, 0x892dfb7d},
    {6, 153, 142, 142, 998, 0x4fad2871},
    {6, 153, 142, 142, 999, 0x9c91ef4c},
    {7, 154, 145, 138, 1033, 0x88998a4d},
    {7, 154, 147, 140, 1035, 0xb14e30ec},
    {8, 154, 148, 135, 1037, 0xe27743b6},
    {8, 154, 151, 136, 1039, 0xdb79e781},
    {9, 154, 153, 132, 1045, 0x61480583},
    {5, 154, 138, 138, 926, 0xe8fe258d},
    {5, 154, 141, 141, 955, 0x0baa5437},
    {6, 154, 144, 144, 1015, 0x5dac3673},
    {6, 154, 151, 148, 1033, 0xc09a79b6},
    {7, 154, 152, 142, 1032, 0x3d768021},
    {7, 154, 144, 140, 1035, 0xaa427646},
    {8, 154, 146, 135, 1039, 0x96d6a0ed},
    {4, 154, 133, 133, 843, 0xe8d103db},
    {4, 153, 130, 130, 811, 0xc9729a5e},
    {5, 153, 138, 138, 902, 0x924b3f6c},
    {5, 153, 139, 139, 900, 0x88f38baa},
    {6, 153, 145, 145, 989, 0x34dfbbfb},
    {6, 152, 149, 149, 1006, 0x0bfdc497},
    {7, 152, 151, 50, 390, 0x6bf20307},
    {8, 152, 152, 49, 391, 0x0574e660},
    {9, 152, 153, 49, 384, 0xc2833ef0},
    {8, 152, 149, 48, 388, 0xe011434e},
    {9, 152, 153, 48, 385, 0xee596fe7},
    {5, 151, 146, 50, 385, 0x4b59fe7f},
    {6, 151, 146, 49, 385, 0x793861f7},
    {7, 151, 149, 49, 386, 0x7b9061b4},
    {6, 152, 150, 48, 381, 0x7e56a606},
    {7, 152, 151, 44, 388, 0xcabcfc90},
    {7, 152, 150, 45, 385, 0x8e494c8a},
    {8, 152, 151, 46, 391, 0x88bc3340},
    {8, 152, 150, 45, 390, 0x47e8b11f},
    {9, 153, 152, 44, 388, 0x9cce43f3},
    {5, 152, 150, 48, 388, 0xad1071d7},
    {5, 152, 149, 46, 385, 0xd9588b1a},
    {6, 152, 150, 46, 382, 0x59bdb168},
    {6, 152, 150, 48, 384, 0x784b4f82},
    {7, 152, 151, 42, 386, 0x5ec878a5},
    {7, 152, 152, 43, 391, 0xde4f7cf3},
    {8, 151, 153, 41, 387, 0x06a04b37},
    {8, 151, 153, 44, 393, 0x784f1f73},
    {9, 152, 154, 42, 391, 0x1fe35075},
    {5, 151, 150, 47, 383, 0xe3b9f1f2},
    {5, 151, 148, 18, 153, 0x76775b31},
    {6, 152, 150, 15, 151, 0xce4b7e06},
    {6, 152, 151, 15, 141, 0xdcbe1004},
    {7, 152, 153, 16, 154, 0x92838755},
    {7, 152, 154, 14, 153, 0xbd4c067e},
    {8, 151, 154, 18, 157, 0x07f67e3c},
    {9, 151, 154, 15, 150, 0x480e5f7c},
    {10, 151, 154, 17, 154, 0x4b713768},
    {5, 150, 152, 15, 153, 0xec7e5573},
    {5, 150, 150, 18, 154, 0xa43534cd},
    {6, 150, 150, 17, 159, 0xb3b3ae4c},
    {7, 150, 151, 17, 155, 0x96940092},
    {8, 150, 151, 16, 152, 0x1c9a6314},
    {7, 150, 150, 15, 158, 0x67d65208},
    {8, 150, 151, 15, 157, 0x4718a1e9},
    {8, 150, 151, 17, 154, 0x572d9d19},
    {9, 150, 151, 12, 141, 0xe3068c56},
    {6, 150, 148, 16, 155, 0xa7b33d95},
    {5, 151, 147, 15, 159, 0x438c5406},
    {6, 151, 148, 16, 154, 0x132236c6},
    {6, 151, 149, 15, 154, 0x3764bee6},
    {7, 151, 151, 17, 158, 0x51f852b7},
    {7, 151, 151, 14, 160, 0x7c70b7f7},
    {8, 152, 152, 14, 158, 0x2b22fa6b},
    {8, 152, 151, 4, 56, 0x190dc8ba},
    {9, 152, 151, 3, 49, 0x0890e969},
    {5, 152, 150, 5, 57, 0x4fb085ed},
    {5, 153, 151, 5, 59, 0x2b9638d8},
    {6, 152, 153, 4, 45, 0x88d4fc69},
    {6, 152, 151, 4, 56, 0xe5549eb0},
    {7, 151, 151, 5, 55, 0xe6fe39d6},
    {7, 150, 152, 7, 55, 0x6965f6b7},
    {8, 150, 152, 7, 52, 0xc642ea17},
    {4, 150, 151, 5, 48, 0xdf055f2a},
    {4, 151, 151, 4, 57, 0xeb2fa451},
    {5, 151, 151, 4, 51, 0x7f66aae8},
    {5, 150, 151, 5, 59, 0xfb0dd5ea},
    {6, 149, 151, 6, 56, 0x466cae18},
    {6, 150, 151, 6, 58, 0x6757db2e},
    {7, 150, 151, 5, 49, 0xfe2fa715},
    {8, 149, 151, 6, 50, 0xad803e1a},
    {9, 148, 151, 7, 47, 0xc40fd760},
    {8, 148, 152, 8, 56, 0x2f6a168f},
    {9, 148, 152, 7, 48, 0xb4aa05c8},
    {5, 149, 151, 6, 55, 0xab3e2078},
    {6, 150, 152, 5, 54, 0xa11fdc03},
    {7, 150, 152, 5, 54, 0x8946e700},
    {6, 150, 150, 4, 56, 0xdb33f1f8},
    {7, 149, 150, 109, 1058, 0xf84badb0},
    {7, 149, 148, 108, 1057, 0x293fb7b3},
    {8, 149, 149, 105, 1057, 0xf0799b0e},
    {8, 149, 150, 105, 1054, 0x25c1b042},
    {9, 149, 150, 105, 1061, 0xec541c8c},
    {5, 149, 132, 132, 1015, 0x6745e35c},
    {5, 150, 138, 138, 1022, 0xca4613fd},
    {6, 150, 144, 134, 1038, 0x4b65db56},
    {6, 150, 142, 134, 1042, 0x1859c530},
    {7, 150, 143, 130, 1041, 0x687b351f},
    {7, 150, 143, 130, 1041, 0x81156fc6},
    {8, 149, 143, 127, 1037, 0xd2592cb5},
    {8, 149, 146, 125, 1045, 0x34dc6bb2},
    {9, 149, 148, 127, 1042, 0xfcf1ca28},
    {5, 149, 133, 133, 857, 0xb0a00f07},
    {5, 148, 133, 133, 841, 0xbbaa5060},
    {6, 148, 138, 138, 913, 0xc344d4dd},
    {6, 148, 138, 138, 940, 0xf8f0d45c},
    {7, 148, 144, 144, 1004, 0xc843ee8b},
    {7, 147, 139, 139, 968, 0x5d615c9c},
    {8, 147, 142, 142, 1019, 0x62d02ff2},
    {9, 147, 144, 140, 1028, 0x7408e9b2},
    {10, 147, 144, 136, 1030, 0x614b24fd},
    {5, 147, 131, 131, 858, 0x3ebe25f1},
    {5, 148, 129, 129, 864, 0x43e4cd52},
    {6, 148, 135, 135, 946, 0xc31e115a},
    {7, 148, 140, 140, 1006, 0x29d229fc},
    {8, 147, 143, 143, 1038, 0x5f4232fb},
    {7, 147, 143, 143, 997, 0x84236cdf},
    {8, 147, 145, 145, 1027, 0x41355c3a},
    {8, 147, 142, 142, 1010, 0x7c6c4417},
    {9, 146, 144, 142, 1021, 0xed883507},
    {6, 146, 127, 127, 833, 0x0e229f0a},
    {5, 146, 119, 119, 762, 0x3c8e2817},
    {6, 146, 125, 125, 831, 0x186fe4e3},
    {6, 146, 128, 128, 848, 0xf331e7eb},
    {7, 146, 132, 132, 897, 0xa50c9c01},
    {7, 146, 133, 133, 908, 0xd00fcbc2},
    {8, 146, 138, 138, 960, 0xaab317be},
    {8, 145, 138, 138, 966, 0x29893d9d},
    {9, 145, 141, 141, 1028, 0xa5725869},
    {5, 145, 131, 131, 868, 0x2caeea52},
    {5, 145, 131, 131, 862, 0x9262f328},
    {6, 145, 135, 135, 933, 0x01795b88},
    {6, 145, 135, 135, 936, 0xd9e9bfde},
    {7, 145, 139, 139, 986, 0x538a94a1},
    {7, 144, 141, 141, 995, 0xfc689fad},
    {8, 144, 144, 144, 1033, 0x88e978a1},
    {4, 144, 112, 56, 380, 0xdf8d2fcc},
    {4, 144, 115, 58, 383, 0x5e9e5d7e},
    {5, 145, 128, 50, 389, 0x73b5f8ed},
    {5, 145, 127, 51, 386, 0x188bdb3d},
    {6, 145, 140, 48, 387, 0xcfb5513b},
    {6, 145, 138, 49, 386, 0xbf159e52},
    {7, 144, 139, 49, 391, 0x3103690d},
    {8, 145, 140, 46, 389, 0xdb0aaf01},
    {9, 145, 142, 45, 387, 0xaa082309},
    {8, 145, 142, 45, 384, 0xb286e57b},
    {9, 145, 143, 45, 387, 0x60ee7298},
    {5, 145, 137, 48, 378, 0xda6f2f82},
    {6, 145, 141, 47, 390, 0x9eaf1c54},
    {7, 145, 142, 46, 389, 0xb69a1ba5},
    {6, 145, 142, 47, 390, 0xa23ecaac},
    {7, 145, 143, 45, 390, 0x44061820},
    {7, 145, 144, 47, 387, 0xfa588a4a},
    {8, 145, 145, 44, 393, 0xfc2b350c},
    {8, 145, 143, 43, 391, 0x9a584061},
    {9, 145, 144, 44, 394, 0x17537c03},
    {5, 146, 139, 47, 390, 0xbb2f14ab},
    {5, 146, 134, 47, 387, 0x5ee39562},
    {6, 146, 140, 46, 385, 0x0ba53b17},
    {6, 146, 143, 43, 394, 0x120ba0cf},
    {7, 147, 145, 15, 160, 0xf1c198e4},
    {7, 147, 140, 17, 158, 0x5334e324},
    {8, 147, 142, 15, 151, 0x68399390},
    {8, 147, 145, 15, 155, 0xfb998c04},
    {9, 147, 146, 14, 155, 0x5ef590bd},
    {5, 147, 147, 17, 154, 0x1a9e4dad},
    {5, 147, 143, 17, 158, 0xe4e6f7d3},
    {6, 147, 143, 16, 157, 0xf3c875b5},
    {6, 147, 144, 15, 155, 0x997a521e},
    {7, 147, 146, 15, 153, 0x5d4c9ffc},
    {7, 147, 147, 15, 155, 0x453cbafe},
    {8, 147, 147, 16, 157, 0xb1ccd5eb},
    {9, 147, 147, 13, 156, 0xe9cb7504},
    {10, 147, 147, 14, 154, 0x1d868a90},
    {5, 148, 143, 15, 157, 0x307c31c3},
    {5, 147, 147, 14, 159, 0xa272c8fa},
    {6, 146, 147, 18, 150, 0x3f011a39},
    {7, 146, 148, 16, 145, 0xc118e28a},
    {8, 146, 148, 15, 154, 0x0f44c2d6},
    {7, 146, 148, 16, 155, 0xe1656c12},
    {8, 146, 148, 17, 156, 0xe57e0565},
    {8, 145, 148, 15, 151, 0x90451f59},
    {9, 146, 149, 17, 155, 0x8b97d01a},
    {6, 146, 146, 16, 157, 0x85801157},
    {5, 147, 146, 5, 52, 0x9038494f},
    {6, 147, 147, 4, 42, 0xb0d9cca6},
    {6, 148, 148, 5, 58, 0x527bfdb1},
    {7, 148, 149, 4, 50, 0x0243bfd9},
    {7, 148, 148, 4, 56, 0xb4d1474e},
    {8, 148, 148, 4, 52, 0xe1063e97},
    {8, 147, 147, 4, 49, 0xa6c7e6c6},
    {9, 147, 147, 4, 57, 0x725c829b},
    {5, 146, 148, 5, 52, 0x55dfee2e},
    {5, 146, 146, 5, 51, 0x5866dd04},
    {6, 146, 147, 5, 51, 0xac3e2558},
    {6, 146, 147, 5, 56, 0x74534558},
    {7, 147, 148, 5, 50, 0x9fd69691},
    {7, 147, 148, 4, 54, 0x9cdd5538},
    {8, 147, 148, 4, 51, 0x34937fae},
    {4, 147, 145, 4, 52, 0x1a410b92},
    {4, 147, 145, 5, 55, 0x4a9759d3},
    {5, 147, 148, 5, 54, 0x5369dbd3},
    {5, 147, 147, 5, 59, 0xd0d53a69},
    {6, 148, 149, 4, 50, 0x90de6a72},
    {6, 148, 148, 5, 59, 0x7bdf9464},
    {7, 148, 149, 5, 57, 0xafc18891},
    {8, 148, 149, 5, 54, 0x86db0d26},
    {9, 149, 150, 5, 57, 0x7d5b2a76},
    {8, 149, 149, 109, 1056, 0x79e0b923},
};
// clang-format on

SceneResult run_scene() {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(2024);
  std::vector<QuantizedEntity> world;
  std::uint32_t next_id = 1;
  for (int k = 0; k < 150; ++k) {
    next_id += 1 + random() % 3;
    world.push_back(scripted_entity(next_id, spec, random));
  }
  SnapshotEncoder encoder(spec);
  SnapshotDecoder decoder(spec);
  std::deque<std::pair<std::uint32_t, std::uint32_t>> acks;  // (arrives at tick, acked tick)
  const std::size_t budgets[] = {1100, 1100, 400, 160, 60};
  Fnv1a hash;
  SceneResult scene;
  wire::Snapshot snapshot, received;
  for (std::uint32_t tick = 1; tick <= 240; ++tick) {
    step_world(world, spec, random);
    if (random() % 6 == 0 && !world.empty()) world.erase(world.begin() + random() % world.size());
    if (random() % 6 == 0) {
      next_id += 1 + random() % 3;
      world.push_back(scripted_entity(next_id, spec, random));
    }
    while (!acks.empty() && acks.front().first <= tick) {
      encoder.acknowledge(acks.front().second);
      acks.pop_front();
    }
    const std::array<float, 3> viewer{static_cast<float>(tick % 60) - 30, 1,
                                      static_cast<float>(tick % 17) * 2 - 16};
    encoder.encode(tick, world, viewer, budgets[(tick / 24) % 5], snapshot);
    const std::string bytes = snapshot.SerializeAsString();
    hash.add(bytes);
    const SnapshotEncodeReport& report = encoder.last_report();
    scene.deferred_snapshots += report.deferred > 0;
    scene.delta_snapshots += report.has_baseline;
    for (const std::uint64_t field :
         {std::uint64_t{report.has_baseline}, std::uint64_t{report.baseline_tick},
          std::uint64_t{report.entities}, std::uint64_t{report.pending}, std::uint64_t{report.sent},
          std::uint64_t{report.deferred}, std::uint64_t{report.bytes}}) {
      hash.add(field);
    }
    scene.ticks.push_back({.baseline_age = snapshot.baseline_age(),
                           .entities = report.entities,
                           .pending = report.pending,
                           .sent = report.sent,
                           .bytes = static_cast<std::uint32_t>(report.bytes),
                           .stream_fnv = folded_fnv(snapshot.entities())});
    EXPECT_TRUE(received.ParseFromString(bytes));
    const SnapshotDecodeResult result = decoder.decode(received);
    EXPECT_TRUE(result.ok) << "tick " << tick << ": " << result.message;
    // The client shows the world but for the entities the budget left out, which it holds at
    // their baseline states (or not at all, or still, when removed).
    if (result.ok) {
      EXPECT_EQ(differing_entities(result.entities, world), report.deferred) << "tick " << tick;
    }
    if (result.ok && tick % 7 != 0) acks.emplace_back(tick + 1 + tick % 9, decoder.newest_tick());
  }
  scene.hash = hash.value();
  return scene;
}

TEST(SnapshotGolden, EncoderOutputIsUnchangedBitForBit) {
  const SceneResult scene = run_scene();
  // The scene reaches the paths that matter: deltas, and budgets that defer entities.
  EXPECT_GT(scene.delta_snapshots, 100);
  EXPECT_GT(scene.deferred_snapshots, 20);
  EXPECT_EQ(scene.hash, 0x13e59c170cf8f0efull) << std::hex << "got 0x" << scene.hash;
  // The first tick and field that differ from the pinned ticks, for the hash alone cannot say.
  ASSERT_EQ(scene.ticks.size(), std::size(kPinnedTicks));
  for (std::size_t k = 0; k < scene.ticks.size(); ++k) {
    const std::string difference = first_difference(kPinnedTicks[k], scene.ticks[k]);
    ASSERT_TRUE(difference.empty()) << "first difference at tick " << k + 1 << ": " << difference;
  }
}

}  // namespace
}  // namespace ricochet::proto::snapshot_golden_test
