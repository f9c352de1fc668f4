#pragma once

/// The schema tables of a net's shackles, `particles.nets[].shackles`, with the brakes and
/// support ropes that may hold them. Declarations of keys only; the checks that relate keys to
/// each other are in io/CaseValidation.cpp.

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

const schema::Table<ShackleConfig>& shackle_table();

}  // namespace ringdem
