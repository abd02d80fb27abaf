#include "stamps.hpp"

#include <filesystem>

#include "plastivox/base/hash.hpp"
#include "plastivox/io/atomic_file.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The digest of a file's bytes, or "" when it cannot be read.
std::string file_digest(const std::string& path) {
  std::string bytes;
  try {
    bytes = read_file_bytes(path, UINT64_MAX);
  } catch (const std::exception&) {
    return "";
  }
  Hasher h;
  h.str(bytes);
  return h.finish().hex();
}

}  // namespace

Stamps::Stamps(const std::string& dir, const std::string& stage)
    : dir_(dir), path_(dir + "/.stamps/" + stage + ".json") {
  try {
    if (fs::exists(path_)) stamps_ = json::parse(read_file_bytes(path_));
  } catch (const std::exception&) {
    stamps_ = json::object();  // unreadable: everything is redone
  }
  if (!stamps_.is_object()) stamps_ = json::object();
}

StampCheck Stamps::check(const std::string& item, const std::string& key,
                         const std::vector<std::string>& files) const {
  StampCheck c;
  const auto it = stamps_.find(item);
  if (it == stamps_.end() || !it->is_object() || it->value("key", json()) != key) return c;
  const json digests = it->value("files", json::object());
  for (const auto& f : files) {
    const auto d = digests.find(f);
    if (d == digests.end() || !d->is_string() || *d != file_digest(dir_ + "/" + f))
      c.damaged.push_back(f);
  }
  c.current = c.damaged.empty();
  return c;
}

void Stamps::record(const std::string& item, const std::string& key,
                    const std::vector<std::string>& files) {
  json digests = json::object();
  for (const auto& f : files) digests[f] = file_digest(dir_ + "/" + f);
  stamps_[item] = {{"key", key}, {"files", digests}};
  fs::create_directories(fs::path(path_).parent_path());
  write_file_atomic(path_, stamps_.dump(1) + "\n");
}

bool up_to_date(const Stamps& stamps, Progress& progress, const std::string& stage,
                const std::string& item, const std::string& key,
                const std::vector<std::string>& files) {
  const StampCheck c = stamps.check(item, key, files);
  if (!c.damaged.empty()) {
    std::string names;
    for (size_t i = 0; i < c.damaged.size(); ++i)
      names += (i == 0 ? "" : i + 1 == c.damaged.size() ? " and " : ", ") + c.damaged[i];
    progress.log("[" + stage + "] " + names + (c.damaged.size() == 1 ? " differs" : " differ") +
                 " from what this study wrote (damaged, edited or deleted): rewriting");
  }
  return c.current;
}

}  // namespace plastivox::experiment
