#pragma once
// What the JSON API's routes share (workspace.cc, animate_routes.cc): the
// refusal a route throws, the app-error-to-status rule, and reading request
// fields, each refusal naming the field at fault. Private to the server.

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rigel/app/workspace.h"
#include "rigel/rig/definition.h"

namespace rigel::server::api {

using Json = nlohmann::ordered_json;
using math::Quat;
using math::Vec3;

// A refused request: status, message, and the request field at fault.
struct ApiError {
  int status = 400;
  std::string message;
  std::string field;
};

[[noreturn]] inline void refuse(int status, std::string message, std::string field = {}) {
  throw ApiError{status, std::move(message), std::move(field)};
}

// The HTTP status of an app error: the input's fault is a bad request,
// what the scene cannot do in its state a conflict.
inline int status_of(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kParseError: return 400;
    case ErrorCode::kNotFound: return 404;
    case ErrorCode::kIoError: return 500;
    default: return 409;
  }
}

inline void check(const Status& s) {
  if (!s) refuse(status_of(s.code()), s.message(), s.field());
}

template <typename T>
T take(Result<T> r) {
  check(r.status());
  return std::move(*r);
}

// ---- request fields ----------------------------------------------------------

inline const Json* opt(const Json& body, const char* key) {
  auto it = body.find(key);
  return it == body.end() || it->is_null() ? nullptr : &*it;
}

inline const Json& need(const Json& body, const char* key) {
  const Json* j = opt(body, key);
  if (!j) refuse(400, std::string("missing field '") + key + "'", key);
  return *j;
}

inline std::string as_string(const Json& j, const std::string& field) {
  if (!j.is_string()) refuse(400, field + ": expected a string, got " + j.type_name(), field);
  return j.get<std::string>();
}

inline double as_number(const Json& j, const std::string& field) {
  if (!j.is_number()) refuse(400, field + ": expected a number, got " + j.type_name(), field);
  const double v = j.get<double>();
  if (!std::isfinite(v)) refuse(400, field + ": not a finite number", field);
  return v;
}

// A whole number, clamped into int's range (the app checks the range it needs).
inline int as_int(const Json& j, const std::string& field, const std::string& expected = "a whole number") {
  const double v = as_number(j, field);
  if (v != std::floor(v)) refuse(400, field + ": expected " + expected, field);
  return static_cast<int>(std::clamp(v, static_cast<double>(INT_MIN), static_cast<double>(INT_MAX)));
}

inline bool as_bool(const Json& j, const std::string& field) {
  if (!j.is_boolean()) refuse(400, field + ": expected true or false, got " + j.type_name(), field);
  return j.get<bool>();
}

template <int N>
Eigen::Matrix<double, N, 1> as_numbers(const Json& j, const std::string& field) {
  if (!j.is_array() || j.size() != N)
    refuse(400, field + ": expected an array of " + std::to_string(N) + " numbers", field);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) v[i] = as_number(j[static_cast<std::size_t>(i)], field + "[" + std::to_string(i) + "]");
  return v;
}

// A rotation: [x, y, z, w] or {"euler": [x, y, z]} (degrees, x first).
inline Quat as_quat(const Json& j, const std::string& field) {
  if (j.is_object()) return app::rotation_from_euler_degrees(as_numbers<3>(need(j, "euler"), field + ".euler"));
  const Eigen::Vector4d v = as_numbers<4>(j, field);
  if (v.norm() < 1e-9) refuse(400, field + ": not a rotation (zero length)", field);
  return Quat(v[3], v[0], v[1], v[2]).normalized();
}

inline Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

// Nodes as [{"uuid", "name"}, ...].
inline Json node_refs_json(const app::Workspace& ws, const std::vector<graph::NodeId>& ids) {
  Json out = Json::array();
  for (graph::NodeId id : ids) {
    const graph::Node* n = ws.graph().node(id);
    out.push_back(Json{{"uuid", n->uuid().str()}, {"name", n->name()}});
  }
  return out;
}

inline Json names_json(const std::vector<std::string>& names) {
  Json list = Json::array();
  for (const std::string& n : names) list.push_back(n);
  return list;
}

inline Json features_json(const std::vector<app::FeatureState>& features) {
  Json list = Json::array();
  for (const app::FeatureState& f : features)
    list.push_back(Json{{"feature", f.feature}, {"switch", f.switch_name}, {"enabled", f.enabled}});
  return list;
}

inline Json problems_json(const std::vector<rig::Diagnostic>& problems) {
  Json list = Json::array();
  for (const rig::Diagnostic& d : problems) list.push_back(Json{{"where", d.str()}, {"message", d.message}});
  return list;
}


// "frames": [first, last] (nullopt when absent).
inline std::optional<std::pair<double, double>> frames_field(const Json& body) {
  const Json* f = opt(body, "frames");
  if (!f) return std::nullopt;
  if (!f->is_array() || f->size() != 2) refuse(400, "frames: expected [first, last]", "frames");
  return std::pair{as_number((*f)[0], "frames"), as_number((*f)[1], "frames")};
}

// A number in a query string ("first=12.5"), refused naming `field` when
// it is not one; query_number: the query's `key`, nullopt when absent.
inline double query_text_number(const std::string& text, const std::string& field) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
    refuse(400, field + ": expected a number, got '" + text + "'", field);
  return v;
}
inline std::optional<double> query_number(const std::map<std::string, std::string>& query, const char* key) {
  auto it = query.find(key);
  if (it == query.end()) return std::nullopt;
  return query_text_number(it->second, key);
}

// An array field of node references, each resolved by `resolve(ref,
// field)` (a Result<NodeId>); nullopt when absent.
template <typename Resolve>
std::optional<std::vector<graph::NodeId>> nodes_field(const Json& body, const char* key, Resolve&& resolve) {
  const Json* c = opt(body, key);
  if (!c) return std::nullopt;
  if (!c->is_array()) refuse(400, std::string(key) + ": expected an array of node names, uuids or rig addresses", key);
  std::vector<graph::NodeId> out;
  for (std::size_t i = 0; i < c->size(); ++i) {
    const std::string field = std::string(key) + "[" + std::to_string(i) + "]";
    out.push_back(take(resolve(as_string((*c)[i], field), field)));
  }
  return out;
}

}  // namespace rigel::server::api
