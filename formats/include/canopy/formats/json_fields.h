// Reading and writing the members of a canopy JSON document (after open_json_document,
// json_document.h): the typed, range-checked field readers every document reader in
// documents/ shares, and the writers' checks. Readers throw MalformedField with "<where><key>
// ...": the document's reader catches it and throws common::DataError naming the file.
#pragma once

#include <array>
#include <exception>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/formats/json_document.h"
#include "canopy/formats/provenance.h"

namespace canopy::formats {

// A value for a message: scalars as JSON text (cut to 40 characters, NUL-safe); arrays and
// objects by kind only (dumping a 30 000-deep nested array would recurse 30 000 frames).
std::string json_describe(const nlohmann::ordered_json& j);

// The message of a JSON library exception without its "[json.exception.x.n] " prefix, quoted
// and cut to 200 characters: for "malformed <document>: <this>".
std::string json_library_text(const std::exception& e);

// An integer within [lo, hi]; 3.0, 1e20 or "3" are not accepted (they would be cast silently).
// `what` names the value ("segments[3].label").
long long json_integer(const nlohmann::ordered_json& j, const std::string& what,
                       long long lo = std::numeric_limits<int>::min(),
                       long long hi = std::numeric_limits<int>::max());

// obj[key] as an int in [lo, INT_MAX], a finite number, a string, an array, 3 numbers; `where` is
// the key's prefix in messages ("segments[3].", "" at the top level). A missing key throws the
// library's out_of_range (the reader reports it through json_library_text).
int json_int_at(const nlohmann::ordered_json& obj, const char* key, const std::string& where,
                long long lo = std::numeric_limits<int>::min());
double json_number_at(const nlohmann::ordered_json& obj, const char* key, const std::string& where);  // finite
std::string json_string_at(const nlohmann::ordered_json& obj, const char* key, const std::string& where);
const nlohmann::ordered_json& json_array_at(const nlohmann::ordered_json& obj, const char* key,
                                            const std::string& where);
std::array<double, 3> json_vec3_at(const nlohmann::ordered_json& obj, const char* key,
                                   const std::string& where);

// The "provenance" object (provenance_json's form): tool, version, string parameters, inputs.
Provenance json_provenance(const nlohmann::ordered_json& j);

// Writers: `v` itself, or common::Error "refusing to write non-finite <what>".
double finite_for_writing(double v, const char* what);
// A document's text as every canopy JSON writer writes it: one-space indent, final newline.
std::string json_document_text(const nlohmann::ordered_json& j);

}  // namespace canopy::formats
