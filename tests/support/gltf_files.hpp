// glTF 2.0 binary (GLB) files read back for the tests: the header and chunks checked, the JSON
// parsed, an accessor's values read from the BIN chunk; and the Khronos glTF validator run on a
// file (tests/io/mesh/validate_gltf.mjs; the tests that use it skip without Node.js and the
// validator, see web_tools.hpp). Needs TINCDT_SOURCE_DIR and tincdt_core (core/json).
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "core/json.hpp"
#include "support/web_tools.hpp"

namespace tincdt::test {

struct GlbFile {
  std::uint32_t version = 0;
  std::uint32_t length = 0;      // the header's total length
  std::uint32_t json_chunk = 0;  // the JSON chunk's length (padding included)
  std::string json_text;
  json::Value json;
  std::string bin;  // the BIN chunk's bytes (padding included); empty without one
};

inline std::uint32_t le32(const std::string& s, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(s[at + i]);
  return v;
}

// BYTES as a GLB: every structural rule checked (a failure is a test failure), the JSON parsed.
inline GlbFile read_glb(const std::string& bytes) {
  GlbFile g;
  EXPECT_GE(bytes.size(), 20u);
  if (bytes.size() < 20) return g;
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  g.version = le32(bytes, 4);
  g.length = le32(bytes, 8);
  EXPECT_EQ(g.version, 2u);
  EXPECT_EQ(g.length, bytes.size());
  g.json_chunk = le32(bytes, 12);
  EXPECT_EQ(bytes.substr(16, 4), "JSON");
  EXPECT_EQ(g.json_chunk % 4, 0u);
  EXPECT_LE(20 + std::size_t{g.json_chunk}, bytes.size());
  if (20 + std::size_t{g.json_chunk} > bytes.size()) return g;
  g.json_text = bytes.substr(20, g.json_chunk);
  g.json = json::parse(g.json_text, "glb JSON chunk");
  std::size_t at = 20 + g.json_chunk;
  if (at < bytes.size()) {
    EXPECT_GE(bytes.size() - at, 8u);
    const std::uint32_t n = le32(bytes, at);
    EXPECT_EQ(bytes.substr(at + 4, 4), std::string("BIN\0", 4));
    EXPECT_EQ(n % 4, 0u);
    EXPECT_EQ(at + 8 + n, bytes.size());
    g.bin = bytes.substr(at + 8, n);
  }
  return g;
}

// The member path A.B.C of V (array items by their number), or null when missing.
inline const json::Value* member(const json::Value& v, std::initializer_list<std::string> path) {
  const json::Value* p = &v;
  for (const std::string& k : path) {
    if (p == nullptr) return nullptr;
    if (p->is(json::Value::Kind::array)) {
      const std::size_t i = std::stoul(k);
      p = i < p->items().size() ? &p->items()[i] : nullptr;
    } else {
      p = p->find(k);
    }
  }
  return p;
}

inline double number_at(const json::Value& v, std::initializer_list<std::string> path) {
  const json::Value* p = member(v, path);
  EXPECT_TRUE(p != nullptr && p->is(json::Value::Kind::number));
  return p != nullptr ? p->number() : -1;
}

// The values of accessor I, as doubles, read from the BIN chunk through its bufferView (float32,
// uint16 or uint32 components; byteStride, if any, honoured).
inline std::vector<double> accessor_values(const GlbFile& g, int i) {
  const std::string a = std::to_string(i);
  const auto view =
      std::to_string(static_cast<int>(number_at(g.json, {"accessors", a, "bufferView"})));
  const auto type = static_cast<int>(number_at(g.json, {"accessors", a, "componentType"}));
  const auto count = static_cast<std::size_t>(number_at(g.json, {"accessors", a, "count"}));
  const json::Value* shape = member(g.json, {"accessors", a, "type"});
  const std::size_t width = shape != nullptr && shape->string() == "VEC3" ? 3 : 1;
  const json::Value* offset = member(g.json, {"accessors", a, "byteOffset"});
  std::size_t at =
      static_cast<std::size_t>(number_at(g.json, {"bufferViews", view, "byteOffset"})) +
      (offset != nullptr ? static_cast<std::size_t>(offset->number()) : 0);
  const std::size_t size = type == 5123 ? 2 : 4;
  const json::Value* stride = member(g.json, {"bufferViews", view, "byteStride"});
  const std::size_t step =
      stride != nullptr ? static_cast<std::size_t>(stride->number()) : width * size;
  EXPECT_EQ(at % size, 0u) << "accessor " << i << " is not aligned";
  std::vector<double> out;
  out.reserve(count * width);
  for (std::size_t e = 0; e < count; ++e, at += step) {
    if (at + width * size > g.bin.size()) {
      ADD_FAILURE() << "accessor " << i << " runs past the BIN chunk";
      break;
    }
    for (std::size_t k = 0; k < width; ++k) {
      const std::size_t p = at + k * size;
      if (type == 5126) {
        float f = 0;
        const std::uint32_t bits = le32(g.bin, p);
        std::memcpy(&f, &bits, 4);
        out.push_back(f);
      } else if (type == 5125) {
        out.push_back(le32(g.bin, p));
      } else {
        out.push_back(static_cast<unsigned char>(g.bin[p]) |
                      (static_cast<unsigned char>(g.bin[p + 1]) << 8));
      }
    }
  }
  return out;
}

// What the Khronos validator says of a file.
struct GltfReport {
  int errors = -1;
  int warnings = -1;
  int infos = -1;
  std::string text;  // the script's output: the counts and the first messages
};

inline GltfReport validate_gltf(const std::string& path) {
  const std::string command = "node '" TINCDT_SOURCE_DIR "/tests/io/mesh/validate_gltf.mjs' '" +
                              web_tools().string() + "' '" + path + "' 2>&1";
  GltfReport r;
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.text.append(buf, n);
  const int status = ::pclose(pipe);
  EXPECT_EQ(status, 0) << r.text;
  if (status != 0) return r;
  try {
    const json::Value v = json::parse(r.text);
    r.errors = static_cast<int>(number_at(v, {"numErrors"}));
    r.warnings = static_cast<int>(number_at(v, {"numWarnings"}));
    r.infos = static_cast<int>(number_at(v, {"numInfos"}));
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the validator's output is not JSON: " << e.what() << "\n" << r.text;
  }
  return r;
}

}  // namespace tincdt::test
