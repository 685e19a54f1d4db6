// The fields' docstrings: each config, input and output field of the module documented by its
// header's member comment (scripts/field_docs.py generates the table at build time, so the text
// lives once, in the header). Applied after every class is bound; a binding's own doc, where it
// has one (a shape, a unit), stays in front of the header's text.
#include "common.hpp"

namespace kiloloop::py_glue {
namespace {

struct FieldDoc {
  const char* cls;
  const char* field;
  const char* doc;
};

constexpr FieldDoc kFieldDocs[] = {
#include "field_docs.inc"
    {nullptr, nullptr, nullptr}};

// The class named `name` in the module or one of its submodules (qp, native, ...), or None.
py::object find_class(py::module_& m, const char* name) {
  if (py::hasattr(m, name)) return m.attr(name);
  for (auto item : m.attr("__dict__").cast<py::dict>()) {
    py::object value = py::reinterpret_borrow<py::object>(item.second);
    if (py::isinstance<py::module_>(value) && py::hasattr(value, name)) return value.attr(name);
  }
  return py::none();
}

}  // namespace

void bind_field_docs(py::module_& m) {
  py::object property = py::module_::import("builtins").attr("property");
  for (const FieldDoc* f = kFieldDocs; f->cls != nullptr; ++f) {
    py::object cls = find_class(m, f->cls);
    if (cls.is_none()) continue;
    py::object members = cls.attr("__dict__");
    if (!members.contains(f->field)) continue;
    py::object prop = members[f->field];
    if (!py::isinstance(prop, property)) continue;
    std::string doc = f->doc;
    const py::object own = prop.attr("__doc__");
    if (!own.is_none()) {
      const std::string text = own.cast<std::string>();
      if (!text.empty() && doc.find(text) == std::string::npos) doc = text + " -- " + doc;
    }
    py::setattr(cls, f->field,
                property(prop.attr("fget"), prop.attr("fset"), prop.attr("fdel"), doc));
  }
}

}  // namespace kiloloop::py_glue
