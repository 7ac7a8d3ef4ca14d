#pragma once
// The nodal temperature file of `temperature: {field: {file: temps.csv}}`: a header row
// "node,<time 1>,<time 2>,..." then one row per node "<tag>,<T at time 1>,...".
#include <istream>
#include <string>

#include "input/yaml_source.hpp"
#include "spec/case.hpp"

namespace hencky::case_input {

/// Reads the file named by `v` (relative to the case file's folder). Every problem is an
/// InputError at the CSV file's line and column with `v`'s key path; the node tags are checked
/// against the mesh later.
TemperatureFile read_temperature_csv(const Reader& r, const Val& v);

/// The rows of an open temperature file into tf.times, tf.node_tags and tf.values; `label` is
/// the file in messages, `key` the case's key that names it.
void read_temperature_rows(std::istream& in, const std::string& label, const std::string& key,
                           TemperatureFile& tf);

}  // namespace hencky::case_input
