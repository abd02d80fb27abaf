// A recorded life: every voxel's pose, size, stiffness, stimulus and floor contact at fixed
// frame times (and, when recorded, the actuation signal and the sensors), in HDF5 (format
// "plastivox-life", layout in docs/results-format.md, "Recorded lives"), so a life can be read with
// h5py and drawn again without simulating (library plastivox_io; not thread-safe, HDF5's serial
// build: call from one thread).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "plastivox/base/error.hpp"  // ResultsError
#include "plastivox/io/provenance.hpp"
#include "plastivox/model.hpp"  // RobotDef, PhysicsDef, Vec3
#include "plastivox/recording.hpp"
#include "plastivox/simulator.hpp"  // SimResult

namespace plastivox {

constexpr int kLifeFormatVersion = 1;

// A life as simulate() left it, with where it came from: the robot, its physics and the
// engine's own summary, whose `recording` holds the frames (fps, frame times in s).
struct RecordedLife {
  std::string source;            // the robot or results file the life came from
  RobotDef robot;                // the robot simulated
  PhysicsDef physics;            // its physics (treatment included)
  std::optional<uint64_t> seed;  // the evolution run's seed, for a run champion
  // simulate()'s summary and frames. The file keeps of it the frames, status (finished or
  // unstable), fitness, settled, com_settled and final_state_hash; read back, the other
  // fields stay at their defaults.
  SimResult result;
  Provenance provenance;  // of the writer (written: current_provenance at writing)
};

// Writes `life` to `path` atomically (built in memory, then a temporary renamed over it).
// Floor contact is written per frame from each frame's poses (floor_contact()). Throws
// ResultsError naming the file.
void write_life_file(const std::string& path, const RecordedLife& life);

// Reads a file written by write_life_file; throws ResultsError naming the file and the
// object for anything missing, mis-shaped or foreign. A sealed life's seal is checked before
// HDF5 reads it; an unsealed one is read in a child process first (child_read.hpp), so a
// damaged file that crashes HDF5 is an error here too, never a signal.
RecordedLife read_life_file(const std::string& path);

// True when `path` is an HDF5 file whose root says format "plastivox-life" (false for a
// results file, which is recognised by its seal before HDF5 reads it, a missing file or
// anything else). An unsealed HDF5 file is asked in a child process, and one that crashes
// HDF5 there counts as a life, for read_life_file to refuse. Never throws.
bool is_life_file(const std::string& path);

}  // namespace plastivox
