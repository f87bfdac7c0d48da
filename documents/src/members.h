// The typed member reading every document reader of documents/ shares (private to
// canopy_documents): each throws formats::MalformedField naming the member
// ("candidates[2].length must be a finite number, not \"4\""); the reader adds the file.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "canopy/formats/json_document.h"

namespace canopy::documents::members {

using Json = nlohmann::ordered_json;
using Malformed = formats::MalformedField;

// A value for a message: scalars as JSON text (cut to 40 characters), arrays and objects by kind.
std::string describe(const Json& v);
// "<where>.<key>", or key when where is empty.
std::string path(const std::string& where, const char* key);
// j[key]; Malformed "<where>: missing "<key>"" when j has no such member.
const Json& at(const Json& j, const char* key, const std::string& where);
// j[key] when j is an object holding key with a value other than null, else nullptr.
const Json* optional(const Json& j, const char* key);

double finite_number(const Json& v, const std::string& what);
std::int64_t count(const Json& v, const std::string& what);  // an integer in [0, 2^53]
std::string text(const Json& v, const std::string& what);
const Json& array(const Json& v, const std::string& what);
const Json& object(const Json& v, const std::string& what);
std::array<double, 3> point3(const Json& v, const std::string& what);  // [x, y, z], finite

// A rigid transform: 16 numbers or 4 rows of 4; the last row 0 0 0 1, the 3 x 3 part a
// rotation (orthonormal within 1e-6, determinant +1).
std::array<double, 16> rigid_matrix(const Json& v, const std::string& what);
// rigid_matrix's check of a row-major 4 x 4 already read: Malformed "<what>: last row is not
// 0 0 0 1" / "...: the 3 x 3 part is not a rotation" / "...: the 3 x 3 part is a reflection".
void check_rigid(const std::array<double, 16>& m, const std::string& what);

// The writers' check: v itself, or common::Error "<tool>: refusing to write a non-finite number".
double finite_or_throw(double v, const char* tool);

// The element prefix prefix + "key[k]." of an array member (the `where` of formats::json_*_at).
std::string item(const std::string& prefix, const char* key, std::size_t k);
// v itself when it is an object, else Malformed "<item without its final dot> must be an object".
const Json& item_object(const Json& v, const std::string& item);

// Inside a reader's catch (...): rethrows the exception being handled as common::DataError(name,
// "malformed <what>: <message>") — a Malformed member with its text, any other std::exception
// (the JSON library's) with formats::json_library_text; a DataError unchanged.
[[noreturn]] void rethrow_malformed(const std::string& name, const char* what);

}  // namespace canopy::documents::members
