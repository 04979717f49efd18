#pragma once

#include <type_traits>
#include <vector>

/// @file
/// The first members of a sequence of pairs: the keys of a map, the names of
/// a list of (name, value) pairs.

namespace systole
{
  /// The first member of every element of @p pairs (a std::map or
  /// std::unordered_map, a vector of std::pair), in the order of @p pairs.
  template <class Pairs>
  auto
  first_members(const Pairs &pairs)
  {
    std::vector<std::remove_const_t<typename Pairs::value_type::first_type>>
      firsts;
    firsts.reserve(pairs.size());
    for (const auto &p : pairs)
      firsts.push_back(p.first);
    return firsts;
  }
} // namespace systole
