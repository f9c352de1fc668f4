#include "engine/ModelTable.hpp"

#include "engine/BodyContactTerm.hpp"
#include "engine/Model.hpp"
#include "engine/PairContactTerm.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "engine/TimoshenkoPlasticBondTerm.hpp"

namespace ringdem {

const std::vector<BondModelEntry>& bond_models() {
  static const std::vector<BondModelEntry> table = {
      {"timoshenko",
       "co-rotational Timoshenko beam, linear elastic, brittle failure by Eq. 3-5 (physics.md §1)",
       [](Model& m) -> std::unique_ptr<BondTerm> {
         return std::make_unique<TimoshenkoBondTerm>(m.bonds, m.bond_types);
       },
       &TimoshenkoBondTerm::create,
       {}},
      {"timoshenko_plastic",
       "the same beam, elastoplastic: plastic elongation and end hinges of the wire bundle, "
       "linear hardening, plastic work; fails by Eq. 3-5 or a plastic strain limit "
       "(docs/physics.md \"Plastic bond\")",
       [](Model& m) -> std::unique_ptr<BondTerm> {
         return std::make_unique<TimoshenkoPlasticBondTerm>(m.bonds, m.plastic_bond_types);
       },
       &TimoshenkoBondTerm::create, TimoshenkoPlasticBondTerm::state_columns(), true},
  };
  return table;
}

const std::vector<ContactModelEntry>& contact_models() {
  static const std::vector<ContactModelEntry> table = {
      {"hertz_mindlin",
       "Hertz normal, Mindlin no-slip tangential with Coulomb cap, restitution damping, "
       "constant-torque rolling friction (physics.md §3)",
       []() {
         std::vector<std::unique_ptr<ForceTerm>> terms;
         terms.push_back(std::make_unique<PairContactTerm>());
         terms.push_back(std::make_unique<BodyContactTerm>());
         return terms;
       }},
  };
  return table;
}

namespace {

template <class Entry>
const Entry* find_in(const std::vector<Entry>& table, std::string_view name) {
  for (const auto& e : table)
    if (e.name == name) return &e;
  return nullptr;
}

template <class Entry>
std::vector<std::string> names_of(const std::vector<Entry>& table) {
  std::vector<std::string> out;
  for (const auto& e : table)
    out.emplace_back(e.name);
  return out;
}

}  // namespace

const BondModelEntry* find_bond_model(std::string_view name) {
  return find_in(bond_models(), name);
}
const ContactModelEntry* find_contact_model(std::string_view name) {
  return find_in(contact_models(), name);
}
std::vector<std::string> bond_model_names() {
  return names_of(bond_models());
}
std::vector<std::string> contact_model_names() {
  return names_of(contact_models());
}

}  // namespace ringdem
