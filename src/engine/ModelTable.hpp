#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "domain/BondStore.hpp"
#include "engine/BondTerm.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {

struct Model;

/// The one table of bond models selectable by name (`bonds[].model`). Adding a model is one
/// line here plus its evaluator (physics/) and its term (engine/).
struct BondModelEntry {
  std::string_view name;
  std::string_view description;
  /// The term over the model's bond store, with the parameters of the model's bond types.
  std::unique_ptr<BondTerm> (*make)(Model& model);
  /// Appends bond `id` between two ends (either order) of type `type`, strengths drawn by
  /// (seed, gid pair); returns its index in the store.
  std::size_t (*create)(BondStore& bonds, const BondTimoshenko::Params& params, std::int32_t type,
                        std::int64_t id, const BondEnd& a, const BondEnd& b, std::uint64_t seed);
  /// The per-bond state columns the law adds to the bond store (BondStore::ModelColumn), or
  /// none.
  std::vector<BondStore::ModelColumn> state_columns = {};
  /// Whether the law reads the plastic limits of its bond types (`bonds[].plastic`, the
  /// model's plastic_bond_types): the loader then requires that section, and refuses it for
  /// laws that do not read it.
  bool plastic = false;
};

/// The one table of contact laws selectable by name (`simulation.contact_model`): each makes
/// the particle–particle and the particle–rigid-body term of its law.
struct ContactModelEntry {
  std::string_view name;
  std::string_view description;
  std::vector<std::unique_ptr<ForceTerm>> (*make)();
};

const std::vector<BondModelEntry>& bond_models();
const std::vector<ContactModelEntry>& contact_models();

/// The entry of that name, or nullptr.
const BondModelEntry* find_bond_model(std::string_view name);
const ContactModelEntry* find_contact_model(std::string_view name);

/// The names of a table, for the case loader's "allowed values" and did-you-mean hints.
std::vector<std::string> bond_model_names();
std::vector<std::string> contact_model_names();

}  // namespace ringdem
