#pragma once

#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// The brake elements of a model (docs/physics.md "Brake elements"), each holding one rigid
/// body (a braked shackle) to the frame. Like the rigid bodies they hold, brakes are few and
/// replicated on every rank, and every rank updates them alike from the bodies' reduced state:
/// no migration, no ghosts. for_each_field() is the registry: the case builds the parameters,
/// checkpoints carry the state (kCheckpoint).
struct BrakeStore {
  std::vector<std::int32_t> body;  ///< the rigid body it holds (index into Model::bodies)
  std::vector<Vec3> anchor;        ///< where it holds the body's centre without load
  std::vector<double> stiffness, activation_force, stroke;  ///< BrakeElement::Params
  std::vector<Vec3> slip;                                   ///< BrakeElement::State
  std::vector<double> travel, work;

  std::size_t size() const { return body.size(); }
  bool empty() const { return body.empty(); }

  /// Appends a brake on `body_index` at its body's centre `at`, with zero state.
  void append(std::int32_t body_index, const Vec3& at, double k, double force, double travel_max) {
    body.push_back(body_index);
    anchor.push_back(at);
    stiffness.push_back(k);
    activation_force.push_back(force);
    stroke.push_back(travel_max);
    slip.push_back({});
    travel.push_back(0.0);
    work.push_back(0.0);
  }

  template <class F>
  void for_each_field(F&& f) {
    fields(*this, f);
  }
  template <class F>
  void for_each_field(F&& f) const {
    fields(*this, f);
  }

 private:
  template <class Self, class F>
  static void fields(Self& s, F& f) {
    using namespace field_flag;
    f(FieldInfo{"body", 0}, s.body);
    f(FieldInfo{"anchor", 0}, s.anchor);
    f(FieldInfo{"stiffness", 0}, s.stiffness);
    f(FieldInfo{"activation_force", 0}, s.activation_force);
    f(FieldInfo{"stroke", 0}, s.stroke);
    f(FieldInfo{"slip", kCheckpoint}, s.slip);
    f(FieldInfo{"travel", kCheckpoint}, s.travel);
    f(FieldInfo{"work", kCheckpoint}, s.work);
  }
};

}  // namespace ringdem
