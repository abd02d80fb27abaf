// What a study stage wrote, so a rerun redoes exactly what is out of date or damaged.
//
// .stamps/<stage>.json holds, per output group (an item), the key of what the group was
// made from (the study fingerprint and the settings the group uses) and a digest of each of
// its files' bytes. A group is current only when its key matches and every file is there
// with the bytes it was written with. A file truncated, overwritten or deleted by hand, or a
// stamp from an older plastivox that held no digests, makes its group redone; check() names
// the damaged files so the log can say what was rewritten.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "progress.hpp"

namespace plastivox::experiment {

struct StampCheck {
  bool current = false;
  std::vector<std::string> damaged;  // files the stamp vouches for whose bytes differ or are gone
};

class Stamps {
 public:
  // The stamps of `dir/.stamps/<stage>.json`; an unreadable stamp file counts as empty.
  Stamps(const std::string& dir, const std::string& stage);

  // Whether `item` was made from `key` and its `files` (relative to dir) are as written.
  StampCheck check(const std::string& item, const std::string& key,
                   const std::vector<std::string>& files) const;
  // Records `item` as made from `key`, with the digests of its files as they are now.
  void record(const std::string& item, const std::string& key,
              const std::vector<std::string>& files);

 private:
  std::string dir_, path_;
  nlohmann::json stamps_ = nlohmann::json::object();
};

// Whether `item` is current. When its key matches but files are damaged, logs
// "[<stage>] a and b differ from what this study wrote (damaged or edited): rewriting".
bool up_to_date(const Stamps& stamps, Progress& progress, const std::string& stage,
                const std::string& item, const std::string& key,
                const std::vector<std::string>& files);

}  // namespace plastivox::experiment
