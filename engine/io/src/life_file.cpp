// The recorded-life file (plastivox/io/life_file.hpp; layout in docs/results-format.md,
// "Recorded lives"). Per-frame fields are datasets of shape (frames, voxels[, 3 or 4]), so
// h5py reads each as one numpy array; the robot and its physics are kept as a plastivox
// robot file (JSON) in an attribute, so the life can be simulated again and its model
// compiled for drawing. The control channels (kControlFrameFields) are written only when
// recorded, flagged by the root attribute "control". Since 2026-12-05 it carries a seal like a
// results file (file_seal.hpp), checked before HDF5 reads it; a life without one is read in a
// child process first (child_read.hpp); every read is checked against the shapes the file
// itself declares.
#include "plastivox/io/life_file.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/child_read.hpp"
#include "plastivox/io/file_seal.hpp"
#include "plastivox/io/h5_util.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/state.hpp"

namespace plastivox {
namespace {

using h5::Ctx;
using h5::Handle;

constexpr const char* kLifeFormat = "plastivox-life";

// True when the HDF5 file at `path` (of `size` bytes) says format "plastivox-life" on its root.
bool has_life_format(const std::string& path, uint64_t size) {
  if (H5Fis_hdf5(path.c_str()) <= 0) return false;
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Handle::Kind::kFile);
  if (file.id() < 0) return false;
  try {
    const Ctx c{path, size};
    Handle root = h5::open_group(c, file.id(), "/");
    return h5::has_attr(root.id(), "format") &&
           h5::read_attr_string(c, root.id(), "/", "format") == kLifeFormat;
  } catch (const ResultsError&) {
    return false;
  }
}

// CPU seconds a child process may take to read an unsealed life of `bytes` (child_read.hpp):
// HDF5 reads a life at hundreds of MB/s; a damaged one made it loop for ever.
int cpu_limit(uint64_t bytes) {
  return 1 + static_cast<int>(std::min<uint64_t>(bytes >> 24, 100000));
}

// The life in the HDF5 file at `path`, every read checked against the shapes it declares.
RecordedLife read_hdf5_life(const std::string& path);

}  // namespace

void write_life_file(const std::string& path, const RecordedLife& life) {
  const Ctx c{path, 0};
  const std::vector<Frame>& frames = life.result.recording.frames;
  const size_t n = frames.empty() ? 0 : frames.front().pos.size();
  for (const Frame& f : frames)
    if (f.pos.size() != n)
      throw ResultsError(path + ": internal error: frames of different voxel counts");
  const hsize_t nf = frames.size(), nv = n;
  const Provenance p = current_provenance(1);
  std::string bytes;
  {
    h5::MemoryFile file(c, seal::kUserBlockBytes);
    {
      Handle root = h5::open_group(c, file.id(), "/");
      const hid_t r = root.id();
      h5::write_attr(c, r, "format", std::string(kLifeFormat));
      h5::write_attr(c, r, "format_version", int64_t{kLifeFormatVersion});
      h5::write_attr(c, r, "source", life.source);
      h5::write_attr(c, r, "robot", robot_to_json(life.robot, &life.physics));
      h5::write_attr(c, r, "treatment", std::string(to_string(life.physics.treatment)));
      if (life.seed) h5::write_attr_u64(c, r, "seed", *life.seed);
      h5::write_attr(c, r, "fps", life.result.recording.fps);
      h5::write_attr(c, r, "frames", static_cast<int64_t>(nf));
      h5::write_attr(c, r, "voxels", static_cast<int64_t>(nv));
      h5::write_attr(c, r, "voxel_size", life.robot.voxel_size);
      h5::write_attr(c, r, "status", std::string(to_string(life.result.status)));
      h5::write_attr(c, r, "fitness", life.result.fitness);
      h5::write_attr(c, r, "settled", int64_t{life.result.settled ? 1 : 0});
      h5::write(c, r, "com_settled",
                std::vector<double>{life.result.com_settled.x(), life.result.com_settled.y(),
                                    life.result.com_settled.z()},
                {3});
      h5::write_attr_u64(c, r, "final_state_hash", life.result.final_state_hash);
      for_each_field(p, [&](const char* name, const auto& v) { h5::write_attr(c, r, name, v); });

      std::vector<double> time;
      for (const Frame& f : frames) time.push_back(f.time);
      h5::write(c, r, "time", time, {nf});
      h5::write_units(c, r, "time", "s");
      // The control channels only when recorded: a default life keeps its size.
      const bool control = life.result.recording.control;
      if (control) h5::write_attr(c, r, "control", int64_t{1});
      for (const auto* table : {&kFrameFields, &kControlFrameFields}) {
        if (table == &kControlFrameFields && !control) break;
        for (const FrameField& f : *table) {
          std::vector<hsize_t> dims = {nf, nv};
          if (f.width > 1) dims.push_back(static_cast<hsize_t>(f.width));
          h5::write(c, r, f.name, frame_channel(frames, f), dims);
          // Every stimulus is in Pa (strain is read as Pa: physics_def.hpp).
          h5::write_units(c, r, f.name, frame_field_unit(f));
        }
      }
      std::vector<uint8_t> contact;
      contact.reserve(nf * nv);
      const GroundDef& ground_def = life.physics.environment.ground;
      const bool on_ground = ground_def.kind != GroundKind::kNone;
      const HeightField ground = on_ground ? make_height_field(ground_def) : HeightField{};
      for (const Frame& f : frames) {
        const std::vector<uint8_t> touching =
            floor_contact(f, life.physics.floor, on_ground ? &ground : nullptr);
        contact.insert(contact.end(), touching.begin(), touching.end());
      }
      h5::write(c, r, "contact", contact, {nf, nv});
      h5::write_units(c, r, "com_settled", "m");
    }
    bytes = file.image();
  }
  seal::seal_image(bytes, path, seal::kLife);
  try {
    write_file_atomic(path, bytes);
  } catch (const InputError& e) {
    throw ResultsError(e.what());
  }
}

bool is_life_file(const std::string& path) {
  h5::quiet_hdf5();
  struct stat sb {};
  if (::stat(path.c_str(), &sb) != 0 || !S_ISREG(sb.st_mode)) return false;
  // Nothing sealed is handed to HDF5 before its seal is checked (file_seal.hpp): a life
  // written since 2026-12-05 starts with its seal's text, a results file with its own.
  if (seal::has_seal(path, seal::kLife)) return true;
  if (seal::has_seal(path, seal::kResults)) return false;
  // Unsealed: HDF5 is asked in a child process (child_read.hpp). A file that crashes it there
  // is taken for a life, so that read_life_file names the damage.
  const uint64_t size = static_cast<uint64_t>(sb.st_size);
  const ChildRead probe = run_in_child(
      [&] {
        if (!has_life_format(path, size)) throw ResultsError(path + ": not a life");
      },
      cpu_limit(size));
  return probe.outcome != ChildRead::Outcome::kError;
}

RecordedLife read_life_file(const std::string& path) {
  // A sealed life is checked whole before HDF5 parses a byte of it: a flipped bit or a changed
  // metadata byte crashed HDF5 1.10 inside a string attribute's read. A results file (sealed
  // as such) is named as one, not handed to HDF5.
  if (seal::has_seal(path, seal::kLife) || seal::has_seal(path, seal::kResults)) {
    seal::check_seal(path, seal::kLife);
    return read_hdf5_life(path);
  }
  // Nothing vouches for an unsealed life (written before seals, 2026-12-05, or its seal cut
  // off), and such a life, damaged, crashed HDF5 (issue 54): it is read in a child process
  // first, and here only once that read succeeded (child_read.hpp).
  const Ctx c = h5::read_context(path);  // a missing file or a folder is said without a process
  const ChildRead probe = run_in_child([&] { read_hdf5_life(path); }, cpu_limit(c.file_size));
  switch (probe.outcome) {
    case ChildRead::Outcome::kOk:
      return read_hdf5_life(path);
    case ChildRead::Outcome::kError:
      throw ResultsError(probe.message);
    case ChildRead::Outcome::kCrashed:
      throw ResultsError(path + ": corrupt (reading it in a separate process ended by " +
                         probe.message + "; the life has no seal to check it by)");
    case ChildRead::Outcome::kNoChild:
      break;
  }
  throw ResultsError(path + ": an unsealed life is read in a separate process, and " +
                     probe.message);
}

namespace {

RecordedLife read_hdf5_life(const std::string& path) {
  const Ctx c = h5::read_context(path);
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw ResultsError(path + ": not an HDF5 file (wrong format, or corrupt or truncated)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), Handle::Kind::kFile);
  if (f.id() < 0) throw ResultsError(path + ": cannot open as HDF5 (corrupt or truncated)");
  Handle root = h5::open_group(c, f.id(), "/");
  const hid_t r = root.id();
  if (!h5::has_attr(r, "format") || h5::read_attr_string(c, r, "/", "format") != kLifeFormat)
    throw ResultsError(path + ": not a plastivox recorded life (no format attribute \"" +
                       std::string(kLifeFormat) + "\" on /)");
  const int64_t version = h5::read_attr_int(c, r, "/", "format_version");
  if (version != kLifeFormatVersion)
    throw ResultsError(path + ": recorded-life format version " + std::to_string(version) +
                       " is not supported (this build reads " + std::to_string(kLifeFormatVersion) +
                       ")");
  RecordedLife life;
  life.source = h5::read_attr_string(c, r, "/", "source");
  try {
    RobotFile rf = parse_robot_json(h5::read_attr_string(c, r, "/", "robot"), path + ": /@robot");
    life.robot = std::move(rf.robot);
    life.physics = rf.physics;
  } catch (const InputError& e) {
    throw ResultsError(e.what());
  }
  if (h5::has_attr(r, "seed")) life.seed = h5::read_attr_u64(c, r, "/", "seed");
  life.result.recording.fps = h5::read_attr_double(c, r, "/", "fps");
  const std::string status = h5::read_attr_string(c, r, "/", "status");
  if (status != "finished" && status != "unstable")
    c.fail("/@status", "expected \"finished\" or \"unstable\", not \"" + status + "\"");
  life.result.status = status == "finished" ? SimStatus::kFinished : SimStatus::kUnstable;
  life.result.fitness = h5::read_attr_double(c, r, "/", "fitness");
  life.result.settled = h5::read_attr_int(c, r, "/", "settled") != 0;
  const std::vector<double> com = h5::read<double>(c, r, "com_settled", 3);
  life.result.com_settled = Vec3(com[0], com[1], com[2]);
  life.result.final_state_hash = h5::read_attr_u64(c, r, "/", "final_state_hash");
  // Files written before 2026-12-05 carry only plastivox_version, git_commit, date_created
  // and host; the fields a file lacks stay empty (zero).
  for_each_field(life.provenance, [&](const char* name, auto& v) {
    if (h5::has_attr(r, name)) h5::read_attr(c, r, "/", name, v);
  });

  // Shapes: the voxel count must be the robot's, every per-frame field (frames, n[, k]).
  int n = 0;
  for (uint8_t present : life.robot.present) n += present ? 1 : 0;
  std::vector<hsize_t> td = {h5::kAnyExtent};
  const std::vector<double> time = h5::read<double>(c, r, "time", td);
  const hsize_t nf = td[0], nv = static_cast<hsize_t>(n);
  for (size_t k = 0; k < nf; ++k) {
    if (!(std::isfinite(time[k]) && (k == 0 || time[k] >= time[k - 1])))
      c.fail("/time", "frame times must be finite and ascending");
    life.result.recording.frames.emplace_back().time = time[k];
  }
  // Lives written before 2026-12-05 have no "control" attribute, and no control channels.
  const bool control = h5::has_attr(r, "control") && h5::read_attr_int(c, r, "/", "control") != 0;
  life.result.recording.control = control;
  for (const auto* table : {&kFrameFields, &kControlFrameFields}) {
    if (table == &kControlFrameFields && !control) break;
    for (const FrameField& f : *table) {
      std::vector<hsize_t> dims = {nf, nv};
      if (f.width > 1) dims.push_back(static_cast<hsize_t>(f.width));
      const std::vector<double> values = h5::read<double>(c, r, f.name, dims);
      set_frame_channel(life.result.recording.frames, f, nv, values.data());
    }
  }
  return life;
}

}  // namespace
}  // namespace plastivox
