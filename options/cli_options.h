#pragma once
// The command-line side of the option registry: a command's options, as CLI11 sees them, come
// from the rows that name the command. The text of each is checked by its row and parsed once,
// here at the edge: a command's own settings straight into the typed fields of its job (bind),
// the tour's settings into `values`, which the scene applies over a scene file or a manifest item.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#include "options/option_registry.h"

namespace meshtour::options {

/// Where a command puts a row's value: parses the row's checked, canonical text into a field.
using Binding = std::function<void(const std::string& text)>;

namespace detail {
template <class T> struct is_optional : std::false_type {};
template <class T> struct is_optional<std::optional<T>> : std::true_type {};

template <class T>
void assign(T& field, const std::string& text) {
  if constexpr (is_optional<T>::value) {
    typename T::value_type value{};
    assign(value, text);
    field = std::move(value);
  } else if constexpr (std::is_same_v<T, bool>) {
    field = text == "true";
  } else if constexpr (std::is_integral_v<T>) {
    field = static_cast<T>(std::stoll(text));
  } else if constexpr (std::is_floating_point_v<T>) {
    field = static_cast<T>(std::stod(text));
  } else {
    field = T(text);  // std::string, std::filesystem::path
  }
}
}  // namespace detail

/// A binding into `field`: bool (a flag), a whole or real number, text or a path, or an optional
/// of one of these (set only when given).
template <class T>
Binding to(T& field) {
  return [&field](const std::string& text) { detail::assign(field, text); };
}

/// A binding through the library's own parser (e.g. text -> enum): `field = parse(text)`.
template <class T, class Parse>
Binding to(T& field, Parse parse) {
  return [&field, parse](const std::string& text) { field = parse(text); };
}

/// `binding`, and the text kept in `values` too (what a farm passes on to its tasks, forwarded_args).
inline Binding recorded(Values& values, std::string_view id, Binding binding) {
  return [&values, id = std::string(id), binding = std::move(binding)](const std::string& text) {
    values[id] = text;
    binding(text);
  };
}

/// The bindings of a command: row id -> where its value goes.
using Bindings = std::map<std::string_view, Binding>;

/// Adds every registry row that `command` takes to `cmd`, in registry order. The rows named in
/// `bound` go to their fields; the others land in `values` (canonical text, checked by the row),
/// and must be settings of the tour or of its video (options::target), which the scene and the
/// video settings read: a command row without a binding is a std::logic_error. Rows that exclude
/// each other (--frames / --seconds) are declared so to CLI11. `values` and the bound fields must
/// outlive the parse.
void add_command_options(CLI::App& cmd, Command command, Values& values, const Bindings& bound);

/// Adds every registry row that `command` takes to `cmd`, all into `values` (for tests and tools
/// that look at the values themselves).
void add_registered_options(CLI::App& cmd, Command command, Values& values);

}  // namespace meshtour::options
