// The lobes of many variants of a case (`cutdyn sweep`): every combination of the values of
// one or more case keys, or a list of whole case files, each run as `cutdyn lobes` runs it, and
// written as one long table — the varied keys first, then the lobes' columns, one row per
// variant and speed. A variant that fails is one row with its error; the others go on. The
// variants are independent, so any front end may share them out (threads, processes, ranks)
// and still write the table of a single run, in the variants' order.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cutdyn/app/report_json.hpp"
#include "cutdyn/app/simulate.hpp"
#include "cutdyn/app/stability.hpp"
#include "cutdyn/io/case_file.hpp"

namespace cutdyn::app {

/// One variant: the case file it comes from (with several files), the varied keys' values,
/// and its case, or why it has none (the problems as the command line prints them).
struct LobesVariant {
  std::string file;
  std::vector<double> values;  // one per varied key, in the order given
  std::optional<io::Case> c;
  std::string error;
};

/// The variants of a sweep over `cases` (one or more, in order) and the keys of `vary`: for
/// each case, the Cartesian product of the keys' values in the order given, the last key
/// varying fastest. A value the case refuses makes a variant with an error, not an exception.
/// Throws InvalidInput (naming `where`) for no case, the same key twice, more than 100 000
/// variants, or when no variant has a case (an unknown key: the request, not a value, is wrong).
std::vector<LobesVariant> lobes_variants(const std::vector<io::Case>& cases,
                                         const std::vector<Sweep>& vary,
                                         const std::string& where = "request");

/// The table's columns: "case" with several cases, the varied keys, the lobes' columns
/// (lobes_table's; the vibration-assisted columns when any case has a [vibration] table), and
/// "error".
std::vector<std::string> lobes_sweep_columns(const std::vector<io::Case>& cases,
                                             const std::vector<Sweep>& vary);

/// The rows of one variant, in `columns`: the lobes of its case by `request`, one row per
/// speed; or, when it has no case or its lobes fail, one row with the error. Never throws for
/// the variant's input; a throw from request.progress (a cancel) passes out.
std::vector<std::vector<io::CsvCell>> lobes_variant_rows(const std::vector<std::string>& columns,
                                                         const LobesVariant& variant,
                                                         const LobesRequest& request);

}  // namespace cutdyn::app
