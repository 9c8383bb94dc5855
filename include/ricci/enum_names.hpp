#pragma once
/// \file
/// Names of enum values from one table per enum: the library prints them, the command line and
/// Python parse them, and the "expected a, b or c" of a parse error lists them, all from the same
/// array. An enum opts in by specialising EnumNames next to its declaration:
///
///     template <> struct EnumNames<Geometry> {
///       static constexpr const char* noun = "geometry";
///       static constexpr std::array<EnumName<Geometry>, 2> names{{
///           {Geometry::Euclidean, "euclidean"}, {Geometry::Hyperbolic, "hyperbolic"}}};
///     };

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricci/errors.hpp"

namespace ricci {

/// How a name of a table shows in the list of a parse error.
enum class NameRole {
  Primary,  ///< the value's printed name (the first Primary entry of a value), listed
  Alias,    ///< also parsed, listed as "(or alias)" after the entry before it
  Hidden,   ///< also parsed, never listed (a spelling kept for old scripts)
};

/// One row of a name table.
template <class E>
struct EnumName {
  E value;
  const char* name;
  NameRole role = NameRole::Primary;
};

/// Specialise with `noun` (what a parse error calls the value, "scheme") and `names` (a
/// constexpr array of EnumName<E> in the order a parse error lists them).
template <class E>
struct EnumNames;

/// The value a name stands for, if any (primary names and aliases alike).
template <class E>
constexpr std::optional<E> find_enum(std::string_view name) {
  for (const EnumName<E>& entry : EnumNames<E>::names) {
    if (name == entry.name) return entry.value;
  }
  return std::nullopt;
}

/// The printed name of a value: its first primary entry, or `fallback` for a value the table
/// lacks (a cast integer).
template <class E>
constexpr const char* enum_name(E value, const char* fallback = "unknown") {
  for (const EnumName<E>& entry : EnumNames<E>::names) {
    if (entry.value == value && entry.role == NameRole::Primary) return entry.name;
  }
  return fallback;
}

/// The primary names in the order of the table: what a command line's choice check and Python's
/// `names` list.
template <class E>
std::vector<std::string> enum_primary_names() {
  std::vector<std::string> names;
  for (const EnumName<E>& entry : EnumNames<E>::names) {
    if (entry.role == NameRole::Primary) names.emplace_back(entry.name);
  }
  return names;
}

/// The listed names as a parse error spells them: "a, b (or b2) or c".
template <class E>
std::string enum_choices() {
  std::string list;
  std::string previous;  // the item being built, written once the next primary arrives
  bool first = true;
  for (const EnumName<E>& entry : EnumNames<E>::names) {
    if (entry.role == NameRole::Hidden) continue;
    if (entry.role == NameRole::Alias) {
      previous += std::string(" (or ") + entry.name + ")";
      continue;
    }
    if (!previous.empty()) {
      list += (first ? "" : ", ") + previous;
      first = false;
    }
    previous = entry.name;
  }
  if (!previous.empty()) list += (first ? "" : " or ") + previous;
  return list;
}

/// The value of a name.
/// \param where the function to name in the message ("parse_scheme")
/// \throw InvalidInput "where: unknown noun 'name'; expected a, b or c"
template <class E>
E parse_enum(const std::string& name, std::string_view where) {
  if (const std::optional<E> value = find_enum<E>(name)) return *value;
  throw InvalidInput(std::string(where) + ": unknown " + EnumNames<E>::noun + " '" + name +
                     "'; expected " + enum_choices<E>());
}

}  // namespace ricci
