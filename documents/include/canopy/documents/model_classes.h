// The classes of models: a CSV of lines "model,class" (share/models/classes.csv gives the thesis
// models theirs; make openset writes one for the vehicle library). score (--model-classes) gives
// true vehicles and model answers their classes from it; classify (--model-classes) the
// modelbase entries without a <model>.class file.
#pragma once

#include <map>
#include <string>

namespace canopy::documents {

// A header line "model,class" first; blank lines and '#' comments are skipped
// (formats::text_lines); a model at most once; a class 1-64 characters of [a-z0-9-]. Throws
// common::DataError(name) naming the line.
std::map<std::string, std::string> parse_model_classes(const std::string& text, const std::string& name);

}  // namespace canopy::documents
