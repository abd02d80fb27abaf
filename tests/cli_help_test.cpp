// plastivox CMD --help, CMD -h and help CMD, for every subcommand: exit 0, the same text,
// the command's own usage line, an example, and every option the command's source takes.
#include <algorithm>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

std::string source(const std::string& relative) {
  std::ifstream in(std::string(PLASTIVOX_SOURCE_DIR) + "/" + relative);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The subcommands main.cpp dispatches (its kCommands rows `{"NAME", cmd_NAME}`), plus version.
std::vector<std::string> dispatched_commands() {
  const std::string main_cpp = source("apps/main.cpp");
  std::vector<std::string> names;
  const std::regex dispatch(R"re(\{"([a-z]+)", cmd_[a-z]+\})re");  // a row of kCommands
  for (auto it = std::sregex_iterator(main_cpp.begin(), main_cpp.end(), dispatch);
       it != std::sregex_iterator(); ++it)
    names.push_back((*it)[1]);
  names.push_back("version");
  return names;
}

// Every "--option" a piece of source takes with take_option / take_flag.
std::set<std::string> options_taken(const std::string& text) {
  std::set<std::string> out;
  const std::regex take(R"re(take_(?:option|flag)\(args, "(--[a-z-]+)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), take); it != std::sregex_iterator();
       ++it)
    out.insert((*it)[1]);
  return out;
}

// The body of an inline helper `NAME(Args& args...)` of apps/render_cli.hpp.
std::string helper_body(const std::string& name) {
  const std::string shared = source("apps/render_cli.hpp");
  const size_t at = shared.find(" " + name + "(Args& args");
  EXPECT_NE(at, std::string::npos) << name << " not found in apps/render_cli.hpp";
  if (at == std::string::npos) return "";
  return shared.substr(at, shared.find("\n}\n", at) - at);
}

// The options a piece of source accepts: those it takes, and those of the shared
// render_cli.hpp helpers it calls.
std::set<std::string> options_accepted(const std::string& text) {
  std::set<std::string> all = options_taken(text);
  for (const char* helper : {"take_frame_style", "take_antialiasing", "take_color_range"})
    if (text.find(std::string(helper) + "(args") != std::string::npos)
      for (const auto& o : options_accepted(helper_body(helper))) all.insert(o);
  return all;
}

// The options one command accepts.
std::set<std::string> options_of(const std::string& command) {
  if (command == "version") return {};
  const std::string cmd = source("apps/cmd_" + command + ".cpp");
  EXPECT_FALSE(cmd.empty()) << "apps/cmd_" << command << ".cpp not found";
  return options_accepted(cmd);
}

TEST(CliHelp, SharedRenderOptionsAreSeen) {
  const auto video = options_of("video");
  for (const char* o : {"--fps", "--size", "--color", "--color-range", "--antialias", "--samples",
                        "--no-scalebar", "--elevation"})
    EXPECT_EQ(video.count(o), 1u) << o;
  EXPECT_EQ(options_of("gallery").count("--color-range"), 1u);
}

TEST(CliHelp, MainDispatchesTheSeventeenCommands) {
  EXPECT_EQ(dispatched_commands().size(), 17u);
}

TEST(CliHelp, EveryCommandHasItsOwnHelpWithEveryOptionAndAnExample) {
  for (const std::string& c : dispatched_commands()) {
    SCOPED_TRACE(c);
    const testing::Output long_form = cli(c + " --help");
    ASSERT_EQ(long_form.status, 0) << long_form.out;
    EXPECT_EQ(long_form.out.rfind("usage: plastivox " + c, 0), 0u) << long_form.out;
    EXPECT_NE(long_form.out.find("example"), std::string::npos) << long_form.out;
    EXPECT_NE(long_form.out.find("  plastivox " + c), std::string::npos)
        << "the example runs the command itself:\n"
        << long_form.out;
    for (const std::string& opt : options_of(c))
      EXPECT_NE(long_form.out.find(opt), std::string::npos)
          << c << " --help does not mention " << opt << ":\n"
          << long_form.out;

    const testing::Output short_form = cli(c + " -h");
    EXPECT_EQ(short_form.status, 0);
    EXPECT_EQ(short_form.out, long_form.out);
    const testing::Output help_cmd = cli("help " + c);
    EXPECT_EQ(help_cmd.status, 0);
    EXPECT_EQ(help_cmd.out, long_form.out);
    // Help wins over other arguments, even malformed ones.
    const testing::Output with_args = cli(c + " --bogus 7 --help");
    EXPECT_EQ(with_args.status, 0);
    EXPECT_EQ(with_args.out, long_form.out);
  }
}

TEST(CliHelp, CommandHelpsDiffer) {
  EXPECT_NE(cli("simulate --help").out, cli("video --help").out);
  EXPECT_NE(cli("simulate --help").out, cli("--help").out);
}

TEST(CliHelp, UnknownCommandForHelpIsAUsageError) {
  const testing::Output r = cli("help frobnicate");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("unknown command 'frobnicate'"), std::string::npos) << r.out;
}

// Issue 54: a mistyped command printed the 47-line usage and no suggestion.
TEST(CliHelp, UnknownCommandIsOneLineNamingTheNearestCommands) {
  const auto one_line = [](const testing::Output& r) {
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  };
  testing::Output r = cli("simulte");
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_EQ(r.out,
            "plastivox: unknown command 'simulte'; did you mean simulate? (plastivox --help "
            "lists the commands)\n");
  r = cli("help rendr");
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("did you mean render?"), std::string::npos) << r.out;
  r = cli("vide");
  one_line(r);
  EXPECT_NE(r.out.find("did you mean video?"), std::string::npos) << r.out;
  r = cli("frobnicate");  // nothing near: the commands, still one line
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("unknown command 'frobnicate' (the commands: help, version, simulate"),
            std::string::npos)
      << r.out;
}

TEST(CliHelp, UsageErrorsPointToTheCommandsHelp) {
  const testing::Output r = cli("inspect --bogus");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.out.find("unknown option --bogus"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("plastivox inspect --help"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace plastivox
