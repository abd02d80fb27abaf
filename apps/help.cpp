// Per-command usage: `plastivox CMD --help`, `plastivox CMD -h` and `plastivox help CMD`
// print the same text. Every option a command takes is listed here (tests/cli_help_test.cpp
// checks this against the options each apps/cmd_*.cpp takes).
#include <algorithm>
#include <string>
#include <vector>

#include "cli.hpp"

namespace plastivox::cli {
namespace {

struct CommandHelp {
  const char* name;
  const char* text;
};

// The frame-style options render and video share (apps/render_cli.hpp take_frame_style).
#define PLASTIVOX_FRAME_OPTIONS                                                            \
  "  --size WxH            image size in pixels (default 1280x720)\n"                      \
  "  --color MODE          congenital (default), stiffness, change, alpha, phase,\n"       \
  "                        stimulus (the treatment's, docs/plasticity.md) or actuation\n"  \
  "                        (the signal; docs/control.md)\n"                                \
  "  --color-range R       data (default: the values shown, rounded to readable ticks)\n"  \
  "                        or paper (fixed: E 1e5..1e11 Pa, change over that range)\n"     \
  "  --no-overlay          no overlays at all; or one by one: --no-colorbar, --no-time,\n" \
  "                        --no-treatment, --no-displacement, --no-scalebar\n"             \
  "  --camera PATH         life (default: framed from the whole life, body and floor in\n" \
  "                        view throughout) or follow (per frame; video draws while it\n"  \
  "                        simulates)\n"                                                   \
  "  --ortho               orthographic camera (default perspective)\n"                    \
  "  --flat                no lighting; --no-shadows: no floor shadows\n"                  \
  "  --zoom Z              camera zoom factor (default 1)\n"                               \
  "  --azimuth DEG         camera azimuth (default -60); --elevation DEG (default 25)\n"

#define PLASTIVOX_ANTIALIAS_OPTIONS(dflt)                     \
  "  --antialias MODE      msaa, edge or none (default " dflt \
  ")\n"                                                       \
  "  --samples N           multisampling with N samples, 1..8 (overrides --antialias)\n"

const CommandHelp kHelp[] = {
    {"simulate",
     "usage: plastivox simulate [ROBOT] [options]\n"
     "       plastivox simulate BASE.vxa --vxd ROBOT.vxd [options]\n"
     "Simulate one robot's life and print a summary. ROBOT is a plastivox robot (.json,\n"
     "docs/robot-format.md) or a VXA file (.vxa); without ROBOT, the built-in ~500-voxel\n"
     "demo walker under stress development. With --vxd, BASE.vxa and ROBOT.vxd are\n"
     "voxcraft-sim's input (its palette, phases, gravity, floor, stop time; docs/vxa.md).\n"
     "options:\n"
     "  --vxd ROBOT.vxd       voxcraft-sim's robot file, merged into BASE.vxa\n"
     "  --treatment T         none, stress, pressure, strain, strain_energy, contact or\n"
     "                        kinetic (default: the file's own; docs/plasticity.md)\n"
     "  --task NAME           what the fitness measures: walk, jump, turn, rough, climb,\n"
     "                        slope, obstacles, carry or push (default: the file's own, else\n"
     "                        walk; docs/tasks.md; parameters: --physics '{\"task\": {...}}')\n"
     "  --preset NAME         physics preset gecco2018-code or gecco2018-paper\n"
     "  --duration S          life length in seconds\n"
     "  --physics JSON        override physics fields, e.g. '{\"self_collision\": false}'.\n"
     "                        Order: the file's physics, --preset, --physics (a \"preset\"\n"
     "                        in it: that preset, for the file's treatment and task),\n"
     "                        then --treatment, --task and --duration, which win over it\n"
     "                        (docs/robot-format.md, \"Resolving a run's physics\")\n"
     "  --controller JSON     the robot's controller instead of its own: {\"kind\": ...,\n"
     "                        \"hidden\": ..., \"every\": ..., \"weights\": [...]}\n"
     "                        (docs/control.md)\n"
     "  --json                print one JSON object (fitness, final_state_hash, ...)\n"
     "  --timings             also report the wall time of each stage of a step\n"
     "                        (\"stage_seconds\" in the JSON)\n"
     "  --record FILE         keep the life's frames: LIFE.h5 (a recorded life: poses, sizes,\n"
     "                        stiffness, stimulus, floor contact; docs/results-format.md) or\n"
     "                        LIFE.history (voxcraft-viz's history format)\n"
     "  --fps F               frames per simulated second of --record (default 30)\n"
     "  --record-control      also record the actuation signal and the sensors in LIFE.h5\n"
     "                        (docs/control.md; for --color actuation)\n"
     "exit status: 0 done, 1 bad input, 2 bad command line, 3 unstable simulation or a\n"
     "life that sank through the floor (invalid unless --physics '{\"sinking_invalid\":\n"
     "false}', the authors' rule; docs/engine.md)\n"
     "examples:\n"
     "  plastivox simulate examples/walker.json --treatment pressure --json\n"
     "  plastivox simulate examples/walker.json --record life.h5 --fps 30\n"},
    {"demo",
     "usage: plastivox demo\n"
     "Simulate the built-in demo walker under each treatment (none, stress, pressure) and\n"
     "print fitness and stiffness change side by side. Takes no options.\n"
     "example:\n"
     "  plastivox demo\n"},
    {"evolve",
     "usage: plastivox evolve --config FILE --out RESULTS.h5 [--config FILE --out R.h5 ...]\n"
     "Run an evolution (AFPO over four CPPNs; with \"algorithm\": \"map-elites\" in the config\n"
     "MAP-Elites over the same genomes in a grid of descriptors; with \"cma-es\" CMA-ES on a\n"
     "fixed body's controller, phases or materials) into an HDF5 results file.\n"
     "The same command resumes a killed run from its last checkpoint (docs/evolution.md).\n"
     "Several --config / --out pairs evolve at once, sharing one pool of worker threads.\n"
     "options:\n"
     "  --config FILE         evolution config (JSON); repeat for several runs\n"
     "  --out RESULTS.h5      results file (new, or resumed if it exists), one per --config\n"
     "  --threads N           worker threads (default: the config's; 0 = all cores)\n"
     "  --task NAME           score lives on this task (walk, jump, turn, rough, climb,\n"
     "                        slope, obstacles, carry or push; docs/tasks.md), not the config's;\n"
     "                        a run of another task is not resumed\n"
     "  --print-default-config  print a commented default config and exit\n"
     "  --stop-after N        stop after N generations as if killed (for testing resume)\n"
     "examples:\n"
     "  plastivox evolve --print-default-config > run.json\n"
     "  plastivox evolve --config run.json --out run.h5 --threads 2\n"},
    {"inspect",
     "usage: plastivox inspect RESULTS.h5 [--json]\n"
     "Summarise a results file: treatment, seed, generations done, champion, content digest.\n"
     "options:\n"
     "  --json                print one JSON object\n"
     "example:\n"
     "  plastivox inspect run.h5 --json\n"},
    {"hausdorff",
     "usage: plastivox hausdorff A B [options]\n"
     "Hausdorff distance between two robots' filled voxels (.json or .vxa), in voxel lengths,\n"
     "minimised over B's placements.\n"
     "options:\n"
     "  --rotations R         none, paper (the paper's 8 orientations, default) or all (24)\n"
     "  --translation T       none or integer (optimal integer shift; default with all)\n"
     "  --json                print one JSON object\n"
     "example:\n"
     "  plastivox hausdorff examples/pi.json examples/gamma.json --rotations all --json\n"},
    {"export",
     "usage: plastivox export RESULTS.h5|ROBOT --out ROBOT.vxa|ROBOT.json [--generation G]\n"
     "       plastivox export RESULTS.h5|ROBOT --format voxcraft --out DIR [--lossy]\n"
     "       plastivox export --demo NAME --out ROBOT.vxa|ROBOT.json\n"
     "Write a run's champion (or a robot file) as a VXA file (for the authors' simulator) or\n"
     "a plastivox robot file; the extension of --out chooses. --format voxcraft writes\n"
     "DIR/base.vxa and DIR/robot.vxd for voxcraft-sim (stiffness as a palette of at most 78\n"
     "materials; the largest stiffness error is printed; docs/vxa.md).\n"
     "options:\n"
     "  --out FILE|DIR        .vxa or .json; a directory under --format voxcraft\n"
     "  --format voxcraft     voxcraft-sim's base.vxa + robot.vxd\n"
     "  --lossy               drop (with a warning each) what voxcraft-sim cannot express,\n"
     "                        such as development, instead of refusing\n"
     "  --generation G        the champion at generation G (default: the last)\n"
     "  --demo NAME           a built-in example robot instead: walker, pi, gamma, upsilon\n"
     "                        or mixture (examples/ holds them), stress development\n"
     "examples:\n"
     "  plastivox export run.h5 --out champion.vxa\n"
     "  plastivox export examples/pi.json --format voxcraft --out pi_voxcraft --lossy\n"
     "  plastivox export --demo pi --out pi.json\n"},
    {"analyze",
     "usage: plastivox analyze [TREATMENT=]FILE [...] --out DIR [options]\n"
     "Analyse run champions: robustness, canalization, diversity, body plans and bootstrap\n"
     "statistics -> DIR/stats.json, CSV tables, analysis.h5, report.html. Rerun after a kill\n"
     "to resume (docs/analysis.md). Under mpirun the battery's lives are shared by the ranks.\n"
     "inputs: results files (.h5) of any algorithm (afpo, cma-es), or robot files (.json,\n"
     "  .vxa) each scored and audited under its own physics; TREATMENT=FILE labels a robot\n"
     "  file's treatment (none, stress, pressure, ...: its physics' treatment is set so), and\n"
     "  must equal a results file's. Without a label a file's own treatment counts.\n"
     "options:\n"
     "  --out DIR             output folder\n"
     "  --generation G        analyse the champions of generation G (default: last)\n"
     "  --threads N           worker threads, drawing included (default 0 = all cores)\n"
     "  --robustness-draws N  lives per champion in the robustness test (default 10)\n"
     "  --robustness-sampling S  linear (default) or log\n"
     "  --seed S              seed of the robustness draws and bootstrap (default 1)\n"
     "  --rotations R         none, paper (default) or all, for the Hausdorff diversity\n"
     "  --translation T       none or integer (default integer with --rotations all)\n"
     "  --resamples N         bootstrap resamples (default 10000, at least 100)\n"
     "  --treatments LIST     comma-separated subset of none,stress,pressure\n"
     "  --allow-mixed-physics analyse runs whose physics differ\n"
     "  --keep-artifacts      keep champions whose life is unstable or sank through the\n"
     "                        floor in the statistics and figures (default: excluded)\n"
     "  --keep-vertical       keep champions whose walk, scored in 3-D, owes too much of\n"
     "                        its fitness to vertical motion (vertical share above 0.1,\n"
     "                        |dz| at least 0.25 voxel lengths) in the statistics and\n"
     "                        figures (default: excluded)\n"
     "  --no-viewer           no 3-D viewer in report.html (and no DIR/lives/)\n"
     "  --battery B           also run a robustness battery (default, paper, small or a\n"
     "                        battery file; plastivox robustness --help): its profiles and\n"
     "                        comparisons in stats.json, analysis.h5 and the report\n"
     "example:\n"
     "  plastivox analyze runs/*.h5 --out analysis --threads 2\n"
     "  plastivox analyze none=a.json none=b.json stress=c.vxa stress=d.vxa --out analysis\n"},
    {"robustness",
     "usage: plastivox robustness [TREATMENT=]FILE [...] [options]\n"
     "The robustness battery (docs/analysis.md, \"Robustness battery\"): each run champion's\n"
     "fitness kept (F_perturbed / F_unperturbed) at every severity of every perturbation,\n"
     "its spread over seeds and the area under each curve; per perturbation the treatments'\n"
     "means with 95 % bootstrap CIs and Bonferroni-corrected tests. Lives that go unstable\n"
     "or sink are counted and shown, never averaged in. Inputs as analyze's: results files\n"
     "or robot files (each under its own physics), labelled TREATMENT=FILE or by their own\n"
     "treatment, every champion audited first. Under mpirun the lives are shared by the ranks.\n"
     "options:\n"
     "  --battery B           default (every perturbation), paper (Eq. 2 alone: R), small\n"
     "                        (the default study's) or a battery file (JSON)\n"
     "  --out DIR             write DIR/robustness.json and DIR/robustness.csv\n"
     "  --generation G        the champions of generation G (default: last)\n"
     "  --seed S              seed of the draws and the bootstrap (default 1)\n"
     "  --robustness-draws N  lives of the paper battery (default 10)\n"
     "  --resamples N         bootstrap resamples (default 10000, at least 100)\n"
     "  --threads N           worker threads (default 0 = all cores)\n"
     "  --estimate-only       print the lives, core-seconds and wall time predicted,\n"
     "                        simulating one life only\n"
     "  --allow-mixed-physics, --keep-artifacts, --keep-vertical   as analyze's\n"
     "example:\n"
     "  plastivox robustness runs/*.h5 --battery default --out robustness --threads 2\n"
     "  plastivox robustness stress=examples/pi.json none=examples/gamma.json --battery small\n"},
    {"render",
     "usage: plastivox render ROBOT_OR_RESULTS --out frame.png [options]\n"
     "One frame of a robot's life (or a results file's champion's) as a PNG. A recorded life\n"
     "(simulate --record LIFE.h5) is drawn as recorded, without simulating again.\n"
     "options:\n"
     "  --out FILE            PNG to write\n"
     "  --time T              time of the frame, s (default 0.2), up to the life's end\n"
     "                        (its first step past the duration)\n" PLASTIVOX_FRAME_OPTIONS
         PLASTIVOX_ANTIALIAS_OPTIONS("msaa") "example:\n"
                                             "  plastivox render examples/walker.json --out "
                                             "frame.png --time 1.5 --color stiffness\n"},
    {"video",
     "usage: plastivox video ROBOT_OR_RESULTS --out life.mp4 [options]\n"
     "A robot's life (or a results file's champion's) as a video (default 5.2 s, 30 fps); the\n"
     "extension of --out picks the container: .mp4 (or .m4v) or .mkv. A recorded life\n"
     "(simulate --record LIFE.h5) is drawn from its frames (each video frame shows the first\n"
     "recorded frame at or after its time), without simulating again.\n"
     "options:\n"
     "  --out FILE            video to write\n"
     "  --fps F               frames per second of life time (default 30)\n"
     "  --start S             first time shown, seconds (default 0)\n"
     "  --end S               last time shown, seconds (default: the end of the life)\n"
     "  --stride N            render every Nth frame (default 1)\n"
     "  --codec NAME          auto (default: H.264, else MPEG-4 Part 2) or an encoder "
     "name\n" PLASTIVOX_FRAME_OPTIONS PLASTIVOX_ANTIALIAS_OPTIONS(
         "edge") "example:\n"
                 "  plastivox video "
                 "examples/walker.json --out "
                 "life.mp4 --color change\n"},
    {"view",
     "usage: plastivox view LIFE.h5|RESULTS.h5|ROBOT [...] --out page.html [options]\n"
     "Robots' lives as one self-contained HTML page with an interactive 3-D viewer (three.js\n"
     "from Debian's libjs-three, inlined: it opens from file:// with the network off). Orbit\n"
     "or follow camera, time slider, play/pause at 0.25x-4x, colour by congenital stiffness,\n"
     "stiffness, change E/E0, stimulus, phase or actuation. A recorded life (simulate --record)\n"
     "is shown as recorded; a robot or a results file's champion is simulated once. With\n"
     "several inputs, one viewer and a button per life to load it.\n"
     "options:\n"
     "  --out FILE            page to write (.html)\n"
     "  --fps F               frames per simulated second to record (default 30; not for a\n"
     "                        recorded life, which keeps its own)\n"
     "  --generation G        a results file's champion at generation G (default: the last)\n"
     "example:\n"
     "  plastivox view run.h5 --out champion.html\n"},
    {"gallery",
     "usage: plastivox gallery RESULTS.h5 [RESULTS.h5 ...] --out gallery.png [options]\n"
     "The run champions side by side, coloured by stiffness (the paper's Figs. 2-4).\n"
     "options:\n"
     "  --out FILE            PNG to write\n"
     "  --size WxH            image size in pixels\n"
     "  --columns N           tiles per row (default 0 = automatic)\n"
     "  --time T              time shown, seconds (default -1 = the end of settling)\n"
     "  --no-labels           no labels (run, seed and fitness under each tile)\n"
     "  --no-colorbar         no colour bar\n"
     "  --color-range R       data (default: the champions' own E0 range) or paper "
     "(fixed)\n"
     "  --e0-range LO,HI      colour E0 over exactly LO..HI Pa instead (e.g. to match\n"
     "                        another gallery's: its JSON sidecar or log gives the "
     "range)\n" PLASTIVOX_ANTIALIAS_OPTIONS("msaa") "example:\n"
                                                    "  plastivox "
                                                    "gallery "
                                                    "runs/"
                                                    "stress-*.h5 "
                                                    "--out "
                                                    "stress.png\n"},
    {"archive",
     "usage: plastivox archive RESULTS.h5 --out DIR [options]\n"
     "A MAP-Elites run's archive (docs/evolution.md, \"MAP-Elites\"): DIR/archive.svg and\n"
     "DIR/archive.png (two descriptors, each cell coloured by its best elite's fitness, empty\n"
     "cells grey), DIR/qd.svg and DIR/qd.png (the QD score and coverage over evaluations),\n"
     "DIR/archive.csv (every elite: cell, bins, descriptors, fitness, ids) and DIR/elites.png\n"
     "(a gallery of the best elites, each simulated under the run's physics). A study on\n"
     "MAP-Elites (plastivox experiment) draws the same for each run in archives/<run>/.\n"
     "options:\n"
     "  --out DIR             folder to write (created if needed)\n"
     "  --axes X,Y            the two descriptors shown (default: the config's first two;\n"
     "                        the best elite over any others)\n"
     "  --elites N            elites in the gallery, best first (default 12)\n"
     "  --size WxH            the gallery's size in pixels\n"
     "  --no-gallery          the map, QD curve and table only (nothing simulated)\n"
     "example:\n"
     "  plastivox archive run.h5 --out archive\n"},
    {"figures",
     "usage: plastivox figures STATS.json --out DIR [options]\n"
     "Fig. 5 panels A-F (PNG and SVG) from plastivox analyze's stats.json.\n"
     "options:\n"
     "  --out DIR             output folder\n"
     "  --size WxH            panel size in pixels\n"
     "  --format LIST         png, svg or png,svg (default png,svg)\n"
     "  --no-combined         no combined figure, panels only\n"
     "example:\n"
     "  plastivox figures analysis/stats.json --out figures\n"},
    {"experiment",
     "usage: plastivox experiment [--config FILE | --preset NAME] --out DIR [options]\n"
     "The whole study in one folder: evolve every run, analyse, render, report. Resumable:\n"
     "after a kill or Ctrl-C the same command continues (docs/experiment.md). The runs\n"
     "evolve by AFPO or, with \"algorithm\": \"map-elites\" in the config's evolution, by\n"
     "MAP-Elites (each run's archive then drawn into DIR/archives/ and the report).\n"
     "options:\n"
     "  --config FILE         experiment config (JSON; see examples/experiment.json and\n"
     "                        examples/experiment-map-elites.json)\n"
     "  --preset NAME         default (used without --config), tiny, gecco2018, one\n"
     "                        task's baseline (docs/tasks.md): walk, jump, turn, rough,\n"
     "                        climb, slope, obstacles, carry or push; or the controller\n"
     "                        study's walk-distributed or rough-distributed\n"
     "  --out DIR             output folder\n"
     "  --threads N           worker threads, drawing included (default: the config's;\n"
     "                        0 = all cores)\n"
     "  --force STAGE,...     redo these stages: evolution, analysis, rendering, report\n"
     "  --run LABEL           evolve only this run (e.g. stress-1), for cluster jobs\n"
     "  --estimate-only       print the cost estimate and exit\n"
     "  --cores N             with --estimate-only: predict for N cores (default: this run's)\n"
     "  --ranks R             with --estimate-only: ... split into R MPI ranks (default 1)\n"
     "  --json                with --estimate-only: also print the prediction as JSON\n"
     "  --no-viewer           no 3-D viewer in report.html (and no DIR/lives/)\n"
     "  --keep-artifacts      keep champions whose life is unstable or sank through the\n"
     "                        floor in the statistics and figures (default: excluded)\n"
     "  --keep-vertical       keep champions whose walk, scored in 3-D, owes too much of\n"
     "                        its fitness to vertical motion (vertical share above 0.1,\n"
     "                        |dz| at least 0.25 voxel lengths) in the statistics and\n"
     "                        figures (default: excluded)\n"
     "  --print-preset NAME   print a preset's config and exit\n"
     "example:\n"
     "  plastivox experiment --preset tiny --out smoke --threads 2\n"},
    {"optimize",
     "usage: plastivox optimize ROBOT --out OPTIMISED.json [options]\n"
     "Gradient ascent of a robot's fitness through its life: each step takes the gradient of\n"
     "the robot's life (docs/gradients.md), judges that life as `simulate` does and moves the\n"
     "arrays --wrt names. Writes the best robot seen (--out, the robot writer's format by\n"
     "extension) and a JSON-lines log: a header (inputs, physics, version, date), one line\n"
     "per step {step, fitness, gradient_norm, seconds}, and a last line {written, step,\n"
     "fitness}: the fitness `plastivox simulate OPTIMISED.json` gives, bit for bit. Progress\n"
     "per step on stderr. Any task, environment, controller and bond model the robot's\n"
     "physics names (the gradient covers them all; a life over --memory-limit is refused\n"
     "in one line). Resumable: after every step the run's state goes to OUT.resume.json;\n"
     "after a kill the same command continues from it to the same bits (removed once OUT\n"
     "is written; another run's checkpoint is refused).\n"
     "options:\n"
     "  --out ROBOT           the optimised robot (.json keeps every value exactly; .vxa)\n"
     "  --wrt A,B             what to optimise: stiffness, phase, dev_rate, act_amplitude\n"
     "                        (the robot's own amplitudes), act_scale (each voxel's\n"
     "                        actuation scale; a robot without one starts at 1 and is\n"
     "                        written with the array; --out .json), amplitude (physics\n"
     "                        act_amplitude, written with the robot), controller (a\n"
     "                        network's weights; default phase,stiffness); stiffness stays\n"
     "                        in [e_min, e_max], an amplitude in [0, 0.9), an act_scale in\n"
     "                        [0, 1], a phase is wrapped into [-0.5, 0.5] cycles\n"
     "  --method M            adam (default) or sgd (plain gradient ascent)\n"
     "  --steps N             gradient steps (default 10); the robot after the last is\n"
     "                        simulated too\n"
     "  --lr X                step size (default 0.01): a step moves a phase by about X\n"
     "                        cycles, a stiffness by about X of itself (Adam; log E), a rate\n"
     "                        by about X per s, a weight, an amplitude or an act_scale by\n"
     "                        about X\n"
     "  --log FILE            the log (default: OUT with .log.jsonl for its extension)\n"
     "  --memory-limit MB     refuse a life whose gradient would need more (default 2048)\n"
     "  --threads N           threads for the backward pass (default 0 = all cores; it uses\n"
     "                        at most 2, the same bits on any number)\n"
     "  --treatment T         development (default: the file's own; docs/plasticity.md)\n"
     "  --preset NAME         physics preset gecco2018-code or gecco2018-paper\n"
     "  --duration S          life length in seconds\n"
     "  --physics JSON        override physics fields, as in plastivox simulate\n"
     "exit status: 0 done, 1 bad input (a life without a gradient, too long for\n"
     "--memory-limit, one that does not count), 2 bad command line\n"
     "example:\n"
     "  plastivox optimize examples/walker.json --wrt phase,stiffness --method adam --steps 5\n"
     "      --duration 0.3 --physics '{\"settle_time\": 0.05}' --out walker-opt.json\n"},
    {"version",
     "usage: plastivox version\n"
     "Print the version and the git commit it was built from.\n"
     "example:\n"
     "  plastivox version\n"},
};

#undef PLASTIVOX_FRAME_OPTIONS
#undef PLASTIVOX_ANTIALIAS_OPTIONS

}  // namespace

const char* command_help(const std::string& command) {
  for (const CommandHelp& h : kHelp)
    if (command == h.name) return h.text;
  return nullptr;
}

bool wants_help(const Args& args) {
  return std::any_of(args.begin(), args.end(),
                     [](const std::string& a) { return a == "--help" || a == "-h"; });
}

}  // namespace plastivox::cli
