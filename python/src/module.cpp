// plastivox._core: the compiled part of the Python module. Errors become the exceptions a
// Python user expects: a bad file -> plastivox.InputError (a ValueError) with the CLI's
// one-line message; a bad argument -> ValueError naming it; a render failure ->
// plastivox.RenderError (a RuntimeError).
#include "bindings.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/vxa.hpp"
#include "plastivox/render/error.hpp"
#include "plastivox_version.hpp"

PYBIND11_MODULE(_core, m) {
  namespace pyb = pybind11;
  m.doc() = "plastivox engine, evolution and renderer (compiled part; use the plastivox package)";
  m.attr("__version__") = PLASTIVOX_VERSION;
  pyb::register_exception<plastivox::InputError>(m, "InputError", PyExc_ValueError);
  pyb::register_exception<plastivox::render::RenderError>(m, "RenderError", PyExc_RuntimeError);
  static const pyb::handle input_error = m.attr("InputError");  // the module keeps it alive
  // Every reader's error type is a bad file to the user: one Python type for all of them.
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const plastivox::VxaError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const plastivox::ResultsError& e) {
      PyErr_SetString(input_error.ptr(), e.what());
    } catch (const plastivox::UsageError& e) {  // a malformed PLASTIVOX_MAX_* variable
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  plastivox::py::bind_physics(m);
  plastivox::py::bind_robot(m);
  plastivox::py::bind_simulate(m);
  plastivox::py::bind_evo(m);
  plastivox::py::bind_render(m);
  plastivox::py::bind_env(m);
  plastivox::py::bind_analysis(m);
  plastivox::py::bind_gradient(m);
}
