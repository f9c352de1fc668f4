#pragma once

#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

#include "domain/ParticleStore.hpp"

namespace ringdem::field_records {

// A store's rows as bytes for MPI, field by field through its registry (for_each_field): the
// fields that carry any of `flags`, in registry order. DomainDecomposition's migration and
// ghost exchange use them; every field list comes from the registry, none is written here.

/// Appends the fields of element i that carry any of `flags` to buf, as bytes, in registry
/// order; unpack_fields reads them back in the same order.
template <class Store>
void pack_fields(Store& s, std::size_t i, unsigned flags, std::vector<char>& buf) {
  s.for_each_field([&](const FieldInfo& f, auto& v) {
    if (!(f.flags & flags)) return;
    const char* src = reinterpret_cast<const char*>(&v[i]);
    buf.insert(buf.end(), src, src + sizeof(v[i]));
  });
}

/// Writes the flagged fields of row i at `out` and returns the end (record_size bytes).
template <class Store>
char* pack_fields_at(Store& s, std::size_t i, unsigned flags, char* out) {
  s.for_each_field([&](const FieldInfo& f, auto& v) {
    if (!(f.flags & flags)) return;
    std::memcpy(out, static_cast<const void*>(&v[i]), sizeof(v[i]));
    out += sizeof(v[i]);
  });
  return out;
}

template <class Store>
const char* unpack_fields(Store& s, std::size_t i, unsigned flags, const char* data) {
  s.for_each_field([&](const FieldInfo& f, auto& v) {
    if (!(f.flags & flags)) return;
    std::memcpy(static_cast<void*>(&v[i]), data, sizeof(v[i]));
    data += sizeof(v[i]);
  });
  return data;
}

template <class Store>
std::size_t record_size(Store& s, unsigned flags) {
  std::size_t n = 0;
  s.for_each_field([&](const FieldInfo& f, auto& v) {
    if (f.flags & flags) n += sizeof(typename std::decay_t<decltype(v)>::value_type);
  });
  return n;
}

}  // namespace ringdem::field_records
