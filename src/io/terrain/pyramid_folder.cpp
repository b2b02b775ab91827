#include "io/terrain/pyramid_folder.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string_view>
#include <system_error>
#include <vector>

#include "core/error.hpp"
#include "core/quoted_text.hpp"

namespace tincdt::io::terrain {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kLayerName = "layer.json";
constexpr std::string_view kTileExtension = ".terrain";

// NAME's value when it is a whole number as the writer spells it: digits, no leading zero.
std::optional<std::uint32_t> decimal(std::string_view name) {
  if (name.empty() || (name.size() > 1 && name.front() == '0')) return std::nullopt;
  std::uint32_t value = 0;
  const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), value);
  if (ec != std::errc() || end != name.data() + name.size()) return std::nullopt;
  return value;
}

// The row of a tile named NAME ("{y}.terrain").
std::optional<std::uint32_t> tile_row(std::string_view name) {
  if (!name.ends_with(kTileExtension)) return std::nullopt;
  return decimal(name.substr(0, name.size() - kTileExtension.size()));
}

std::optional<int> level_of(std::string_view name) {
  const std::optional<std::uint32_t> z = decimal(name);
  if (!z || *z > static_cast<std::uint32_t>(kMaxTileLevel)) return std::nullopt;
  return static_cast<int>(*z);
}

struct Entry {
  std::string name;
  fs::file_type type;  // of the entry itself: a symbolic link is not followed
};

// The entries of FOLDER in name order (so that the first stranger named is always the same); EC
// set when the folder cannot be read.
std::vector<Entry> entries_of(const fs::path& folder, std::error_code& ec) {
  std::vector<Entry> out;
  fs::directory_iterator it(folder, ec);
  for (const fs::directory_iterator end; !ec && it != end; it.increment(ec)) {
    const fs::file_type type = it->symlink_status(ec).type();
    if (ec) break;
    out.push_back({it->path().filename().string(), type});
  }
  std::sort(out.begin(), out.end(), [](const Entry& a, const Entry& b) { return a.name < b.name; });
  return out;
}

std::vector<Entry> readable_entries(const fs::path& folder) {
  std::error_code ec;
  std::vector<Entry> out = entries_of(folder, ec);
  if (ec) throw OutputError(folder.string(), "", "cannot read the folder: " + ec.message());
  return out;
}

bool is_folder(const Entry& e) {
  return e.type == fs::file_type::directory;
}
bool is_file(const Entry& e) {
  return e.type == fs::file_type::regular;
}

// The first entry under DIR, in name order, that is not part of a pyramid, as a path relative to
// DIR ("" when there is none); FIRST_TILE: the first tile, relative to DIR too.
std::string first_stranger(const fs::path& dir, std::string& first_tile) {
  for (const Entry& level : readable_entries(dir)) {
    if (level.name == kLayerName && is_file(level)) continue;
    if (!is_folder(level) || !level_of(level.name)) return level.name;
    for (const Entry& column : readable_entries(dir / level.name)) {
      const std::string at = level.name + "/" + column.name;
      if (!is_folder(column) || !decimal(column.name)) return at;
      for (const Entry& tile : readable_entries(dir / at)) {
        if (!is_file(tile) || !tile_row(tile.name)) return at + "/" + tile.name;
        if (first_tile.empty()) first_tile = at + "/" + tile.name;
      }
    }
  }
  return {};
}

void remove_if_empty(const fs::path& folder) {
  std::error_code ec;
  fs::remove(folder, ec);  // only an empty folder goes; one that is not stays, as it should
}

}  // namespace

void check_pyramid_folder(const std::string& dir, bool overwrite) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return;
  std::string first_tile;
  const std::string stranger = first_stranger(dir, first_tile);
  if (!stranger.empty())
    throw OutputError(dir, "",
                      "holds " + quoted_text(stranger) +
                          ", which is not part of a web terrain pyramid: a pyramid's folder may "
                          "hold only its layer.json and {z}/{x}/{y}.terrain tiles, as a new "
                          "pyramid replaces all of them; move it elsewhere or choose another "
                          "folder");
  if (overwrite) return;
  const fs::path layer = fs::path(dir) / kLayerName;
  if (fs::exists(fs::symlink_status(layer, ec)))
    throw OutputError(layer.string(), "", "already exists", Remedy::overwrite);
  if (!first_tile.empty())
    throw OutputError((fs::path(dir) / first_tile).string(), "", "already exists",
                      Remedy::overwrite);
}

TileRemoval remove_tiles(const std::string& dir, const std::function<bool(const TileKey&)>& keep) {
  TileRemoval r;
  const auto fail = [&r](const fs::path& path, const std::error_code& ec) {
    if (r.failed++ == 0) r.first_failure = path.string() + ": " + ec.message();
  };
  const fs::path root(dir);
  std::error_code levels_ec;
  for (const Entry& level : entries_of(root, levels_ec)) {
    const std::optional<int> z = level_of(level.name);
    if (!is_folder(level) || !z) continue;
    const fs::path level_path = root / level.name;
    std::error_code columns_ec;
    for (const Entry& column : entries_of(level_path, columns_ec)) {
      const std::optional<std::uint32_t> x = decimal(column.name);
      if (!is_folder(column) || !x) continue;
      const fs::path column_path = level_path / column.name;
      std::error_code tiles_ec;
      for (const Entry& tile : entries_of(column_path, tiles_ec)) {
        const std::optional<std::uint32_t> y = tile_row(tile.name);
        if (!is_file(tile) || !y || keep(TileKey{*z, *x, *y})) continue;
        const fs::path path = column_path / tile.name;
        std::error_code ec;
        if (fs::remove(path, ec))
          ++r.removed;
        else if (ec)
          fail(path, ec);
      }
      if (tiles_ec) fail(column_path, tiles_ec);
      remove_if_empty(column_path);
    }
    if (columns_ec) fail(level_path, columns_ec);
    remove_if_empty(level_path);
  }
  if (levels_ec) fail(root, levels_ec);
  return r;
}

}  // namespace tincdt::io::terrain
