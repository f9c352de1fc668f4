#pragma once

/// The schema of a case file: one table per section declaring every key (type, required or
/// default, allowed range, unit, documentation) and the CaseConfig member it fills. The loader
/// parses and dumps with these tables, --set resolves key paths against them and
/// docs/case-file.md is generated from them.

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// The top-level table of a case file; the tables of all sections hang below it.
const schema::Table<CaseConfig>& case_schema();

}  // namespace ringdem
