#include "plastivox/io/json_input.hpp"

#include <cstdint>
#include <limits>
#include <set>
#include <vector>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/base/one_line.hpp"
#include "plastivox/io/file_seal.hpp"
#include "plastivox/task.hpp"

namespace plastivox {

namespace {

// A first, read-only pass over the text (nlohmann's SAX interface, linear): duplicate keys,
// the nesting depth and syntax errors, each with its path. The document is then parsed
// without a callback: nlohmann's callback parser scans the enclosing array at every object's
// end, quadratic in an array of objects (400 000 loads took 75 s).
class InputChecker : public nlohmann::json_sax<nlohmann::json> {
 public:
  InputChecker(const std::string& source, const std::string& field)
      : source_(source), field_(field) {}

  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return open_level(); }
  bool start_array(std::size_t) override { return open_level(); }
  bool end_object() override { return close_level(); }
  bool end_array() override { return close_level(); }
  bool key(string_t& k) override {
    Level& f = open_.back();
    f.last_key = k;
    if (!f.keys.insert(k).second)
      throw InputError(source_ + ": " + (f.path.empty() ? "" : f.path + ".") + k +
                       ": given twice (a key may appear once in an object)");
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) override {
    throw InputError(one_line(source_ + ": " + field_ + ": not valid JSON: " + e.what()));
  }

 private:
  // One frame per open object or array: its path and, for objects, the keys seen so far.
  struct Level {
    std::string path;
    std::set<std::string> keys;
    std::string last_key;
  };

  bool open_level() {
    if (static_cast<int>(open_.size()) >= kMaxJsonDepth) {
      std::string where = open_.back().path;  // the last key, without the "[]" runs
      while (where.size() >= 2 && where.compare(where.size() - 2, 2, "[]") == 0)
        where.resize(where.size() - 2);
      throw InputError(source_ + ": " + (where.empty() ? field_ : where) + ": nested deeper than " +
                       std::to_string(kMaxJsonDepth) + " levels of objects and arrays");
    }
    std::string path;
    if (!open_.empty()) {
      const Level& f = open_.back();
      const std::string name = f.last_key.empty() ? "[]" : f.last_key;
      path = f.path.empty() ? name : f.path + (name == "[]" ? "" : ".") + name;
    }
    open_.push_back({path, {}, {}});
    return true;
  }
  bool close_level() {
    if (!open_.empty()) open_.pop_back();
    return true;
  }

  const std::string& source_;
  const std::string& field_;
  std::vector<Level> open_;
};

}  // namespace

nlohmann::json parse_json_input(std::string_view text, const std::string& source,
                                const std::string& field) {
  using nlohmann::json;
  // A results file or recorded life given where JSON belongs: say what it is, not where its
  // first NUL byte sits.
  if (const std::string hdf5 = seal::describe_hdf5(text); !hdf5.empty())
    throw InputError(source + ": " + field + ": " + hdf5 + ", not JSON");
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw InputError(source + ": " + field + ": not valid JSON: a NUL byte at offset " +
                     std::to_string(nul));
  InputChecker checker(source, field);
  json::sax_parse(text, &checker);  // throws InputError on any problem
  try {
    return json::parse(text);
  } catch (const json::exception& e) {  // not reached: the checker saw the same text
    throw InputError(one_line(source + ": " + field + ": not valid JSON: " + e.what()));
  }
}

nlohmann::json parse_json_file(std::string_view text, const std::string& source,
                               const std::string& format) {
  nlohmann::json j = parse_json_input(text, source);
  if (!j.is_object()) json_field::fail(source, "(file)", "expected a JSON object");
  if (!j.contains("format") || j["format"] != format)
    json_field::fail(source, "format", "expected \"" + format + "\"");
  return j;
}

namespace json_field {

void fail(const std::string& source, const std::string& field, const std::string& what) {
  throw InputError(source + ": " + field + ": " + what);
}

double number(const nlohmann::json& j, const std::string& source, const std::string& field) {
  if (!j.is_number()) fail(source, field, "expected a number");
  return j.get<double>();
}

int integer(const nlohmann::json& j, const std::string& source, const std::string& field) {
  if (!j.is_number_integer()) fail(source, field, "expected an integer");
  const auto v = j.get<int64_t>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(source, field, "is out of range, got " + std::to_string(v));
  return static_cast<int>(v);
}

int integer(const nlohmann::json& j, const std::string& source, const std::string& field, int lo,
            int hi) {
  // Appended piecewise: GCC 12 at -O3 reports a false -Wrestrict on `"[" + std::to_string(lo)`.
  std::string range = "[";
  range += std::to_string(lo);
  range += ", ";
  range += std::to_string(hi);
  range += "]";
  if (!j.is_number_integer()) fail(source, field, "expected an integer in " + range);
  const auto v = j.get<int64_t>();
  if (v < lo || v > hi) fail(source, field, "must be in " + range + ", got " + std::to_string(v));
  return static_cast<int>(v);
}

std::string text(const nlohmann::json& j, const std::string& source, const std::string& field) {
  if (!j.is_string()) fail(source, field, "expected a string");
  return j.get<std::string>();
}

bool boolean(const nlohmann::json& j, const std::string& source, const std::string& field) {
  if (!j.is_boolean()) fail(source, field, "expected true or false");
  return j.get<bool>();
}

TreatmentSpec treatment(const nlohmann::json& j, const std::string& source,
                        const std::string& field) {
  const char* expected = "expected a stimulus name or {\"stimulus\": ..., \"law\": ...}";
  if (!j.is_string() && !j.is_object()) fail(source, field, expected);
  TreatmentSpec t;
  const nlohmann::json* stimulus = &j;
  std::string stimulus_field = field;
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it)
      if (it.key() != "stimulus" && it.key() != "law")
        fail(source, field + "." + it.key(), "unknown field (a treatment has stimulus and law)");
    if (!j.contains("stimulus")) fail(source, field + ".stimulus", "missing");
    stimulus = &j["stimulus"];
    stimulus_field += ".stimulus";
    if (j.contains("law")) {
      const std::string law_field = field + ".law";
      try {
        t.law = parse_growth(text(j["law"], source, law_field));
      } catch (const std::invalid_argument& e) {
        fail(source, law_field, e.what());
      }
    }
  }
  try {
    t.stimulus = parse_treatment(text(*stimulus, source, stimulus_field));
  } catch (const std::invalid_argument& e) {
    fail(source, stimulus_field, e.what());
  }
  return t;
}

ControllerDef controller(const nlohmann::json& c, const std::string& source,
                         const std::string& field, bool with_weights) {
  if (!c.is_object()) fail(source, field, "expected an object {\"kind\": ..., ...}");
  if (!c.contains("kind")) fail(source, field + ".kind", "missing (sine, distributed or central)");
  ControllerDef d;
  for (auto it = c.begin(); it != c.end(); ++it) {
    const std::string& k = it.key();
    const std::string f = field + "." + k;
    if (k == "kind") {
      try {
        d.kind = parse_controller_kind(text(*it, source, f));
      } catch (const std::invalid_argument& e) {
        fail(source, f, e.what());
      }
    } else if (k == "hidden") {
      d.hidden = integer(*it, source, f, 0, kMaxHidden);
    } else if (k == "every") {
      d.every = integer(*it, source, f, 1, 1 << 30);
    } else if (k == "weights" && with_weights) {
      if (!it->is_array()) fail(source, f, "expected an array of numbers");
      for (size_t w = 0; w < it->size(); ++w)
        d.weights.push_back(number((*it)[w], source, f + "[" + std::to_string(w) + "]"));
    } else {
      fail(source, f, "unknown field");
    }
  }
  if (d.kind == ControllerKind::kSine && d.hidden != 0)
    fail(source, field + ".hidden", "the sine has no network: give 0 hidden units or none");
  const int count = weight_count(d.kind, d.hidden);
  if (count < 0)
    fail(source, field + ".hidden",
         "must be in [1, " + std::to_string(kMaxHidden) + "] for " + to_string(d.kind));
  if (with_weights && static_cast<int>(d.weights.size()) != count)
    fail(source, field + ".weights",
         "expected " + std::to_string(count) + " numbers for " + to_string(d.kind) +
             " with hidden " + std::to_string(d.hidden) + ", got " +
             std::to_string(d.weights.size()));
  return d;
}

nlohmann::json controller_json(const ControllerDef& d) {
  nlohmann::json c;
  c["kind"] = to_string(d.kind);
  if (d.kind != ControllerKind::kSine) c["hidden"] = d.hidden;
  c["every"] = d.every;
  if (d.kind != ControllerKind::kSine) c["weights"] = d.weights;
  return c;
}

TaskSpec task(const nlohmann::json& j, const std::string& source, const std::string& field) {
  if (!j.is_string() && !j.is_object())
    fail(source, field, "expected {\"name\": ...} or a task name (" + task_names() + ")");
  const nlohmann::json* name = &j;
  std::string name_field = field;
  if (j.is_object()) {
    if (!j.contains("name")) fail(source, field + ".name", "missing");
    name = &j["name"];
    name_field += ".name";
  }
  TaskSpec t;
  try {
    t.task = parse_task(text(*name, source, name_field));
  } catch (const std::invalid_argument& e) {
    fail(source, name_field, e.what());
  }
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it.key() == "name") continue;
      const std::string f = field + "." + it.key();
      const double v = number(*it, source, f);
      try {
        check_task_param(t.task, it.key(), v);
      } catch (const std::invalid_argument& e) {
        fail(source, f, e.what());
      }
      t.params[it.key()] = v;
    }
  return t;
}

nlohmann::json task_json(Task task, const TaskParams& params) {
  if (params.empty()) return to_string(task);
  nlohmann::json j = {{"name", to_string(task)}};
  for (const auto& [name, value] : params) j[name] = value;
  return j;
}

}  // namespace json_field
std::string first_difference(const nlohmann::json& a, const nlohmann::json& b,
                             const std::string& a_where, const std::string& b_where,
                             const std::string& path) {
  if (a == b) return "";
  const auto side = [](const nlohmann::json* v, const std::string& where) {
    return (v ? v->dump() : std::string("absent")) + " " + where;
  };
  const auto differ = [&](const nlohmann::json* x, const nlohmann::json* y, const std::string& p) {
    return (p.empty() ? std::string("(top level)") : p) + ": " + side(x, a_where) + ", " +
           side(y, b_where);
  };
  if (a.is_object() && b.is_object()) {
    std::set<std::string> keys;
    for (auto it = a.begin(); it != a.end(); ++it) keys.insert(it.key());
    for (auto it = b.begin(); it != b.end(); ++it) keys.insert(it.key());
    for (const std::string& k : keys) {
      const std::string p = path.empty() ? k : path + "." + k;
      const auto x = a.find(k), y = b.find(k);
      if (x == a.end() || y == b.end())
        return differ(x == a.end() ? nullptr : &*x, y == b.end() ? nullptr : &*y, p);
      const std::string d = first_difference(*x, *y, a_where, b_where, p);
      if (!d.empty()) return d;
    }
  }
  if (a.is_array() && b.is_array() && a.size() == b.size())
    for (size_t i = 0; i < a.size(); ++i) {
      const std::string d =
          first_difference(a[i], b[i], a_where, b_where, path + "[" + std::to_string(i) + "]");
      if (!d.empty()) return d;
    }
  return differ(&a, &b, path);
}

}  // namespace plastivox
