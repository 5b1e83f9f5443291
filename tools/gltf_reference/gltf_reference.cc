// gltf_reference: an independent oracle for glTF 2.0 skinning.
//
// Computes the world-space vertex positions of every mesh primitive of a
// glTF file at given times, straight from the glTF 2.0 specification
// (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html), so rigel's
// importer, animation and skinCluster can be checked against code that shares
// nothing with them. It links only tinygltf (parsing JSON/GLB and decoding
// buffers) and Eigen; it must never include a rigel header.
//
//   gltf_reference FILE.glb|FILE.gltf [--times t1,t2,...] [--animation INDEX|none]
//                  [-o OUT.json]
//
// Output (stdout when -o is missing or "-"):
//   {"file": ..., "animation": index or -1, "animation_range": [first key, last key]
//    (seconds; absent without animation), "times": [...],
//    "primitives": [{"node", "node_name", "mesh", "mesh_name", "primitive",
//                    "skinned", "vertex_count",
//                    "positions": [[x0,y0,z0,x1,...] one flat array per time]}],
//    "bounds_diagonal": d, "bind_bounds_diagonal": b}
// Primitives are listed in glTF node order, then primitive order, for nodes
// of the default scene (every root node when the file has no scene).
// `bounds_diagonal`, the model's size, is the diagonal of the bounding box of
// all positions in the rest pose (no animation); `bind_bounds_diagonal` that
// of the bind pose (skinned primitives: POSITION with default morph weights,
// where world(joint) * IBM = identity puts them; unskinned ones: as at rest).
// The two agree unless the skeleton's rest pose differs from its bind pose.
//
// Exit status: 0 on success, 1 on invalid input (unreadable file, bad
// accessor, joint index out of range, ...), 2 on a usage error.

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Mat4 = Eigen::Matrix4d;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// Bad input: reported on stderr, exit status 1.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// ---- Accessors (spec 3.6.2) -------------------------------------------------

// Components per element (3.6.2.1, "type").
int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: throw InputError("unknown accessor type " + std::to_string(type));
  }
}

// Bytes per component (3.6.2.2, "componentType").
int component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: throw InputError("unknown componentType " + std::to_string(component_type));
  }
}

// One little-endian component; normalized integers map to [0, 1] or [-1, 1]
// with the formulas of 3.11 ("Animations", normalized integer table):
// f = max(c / 127, -1), c / 255, max(c / 32767, -1), c / 65535.
double read_component(const unsigned char* p, int component_type, bool normalized) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const double c = static_cast<std::int8_t>(p[0]);
      return normalized ? std::max(c / 127.0, -1.0) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;  // never normalized (3.6.2.2)
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: throw InputError("unknown componentType " + std::to_string(component_type));
  }
}

// Byte layout of one element: matrix columns start on 4-byte boundaries
// (3.6.2.4, "Data Alignment"), which pads MAT2 of bytes and MAT3 of bytes or
// shorts; everything else is tightly packed.
struct ElementLayout {
  int rows = 1, columns = 1, component_bytes = 1, column_bytes = 1;
  int size() const { return columns * column_bytes; }
  int offset(int i) const { return (i / rows) * column_bytes + (i % rows) * component_bytes; }
};

ElementLayout element_layout(int type, int component_type) {
  ElementLayout l;
  l.component_bytes = component_size(component_type);
  const int n = component_count(type);
  const bool matrix = type == TINYGLTF_TYPE_MAT2 || type == TINYGLTF_TYPE_MAT3 || type == TINYGLTF_TYPE_MAT4;
  l.rows = matrix ? static_cast<int>(std::lround(std::sqrt(n))) : n;
  l.columns = n / l.rows;
  l.column_bytes = l.rows * l.component_bytes;
  if (matrix) l.column_bytes = (l.column_bytes + 3) / 4 * 4;
  return l;
}

// Reads `count` elements of `layout` starting at `byte_offset` of a buffer
// view, `stride` bytes apart, into `out` (count * components doubles).
void read_elements(const tinygltf::Model& model, int view_index, std::size_t byte_offset, int stride,
                   std::size_t count, const ElementLayout& layout, int component_type, bool normalized,
                   const std::string& what, double* out) {
  if (view_index < 0 || view_index >= static_cast<int>(model.bufferViews.size()))
    throw InputError(what + ": bufferView " + std::to_string(view_index) + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[view_index];
  if (view.buffer < 0 || view.buffer >= static_cast<int>(model.buffers.size()))
    throw InputError(what + ": buffer " + std::to_string(view.buffer) + " does not exist");
  const std::vector<unsigned char>& data = model.buffers[view.buffer].data;
  if (stride == 0) stride = view.byteStride != 0 ? static_cast<int>(view.byteStride) : layout.size();
  if (count == 0) return;
  const std::size_t end = byte_offset + (count - 1) * stride + layout.size();
  if (end > view.byteLength || view.byteOffset + view.byteLength > data.size())
    throw InputError(what + ": reads past the end of its bufferView/buffer");
  const int n = layout.rows * layout.columns;
  for (std::size_t e = 0; e < count; ++e) {
    const unsigned char* base = data.data() + view.byteOffset + byte_offset + e * stride;
    for (int i = 0; i < n; ++i) out[e * n + i] = read_component(base + layout.offset(i), component_type, normalized);
  }
}

// A decoded accessor: `count` elements of `components` doubles each.
struct Array {
  std::size_t count = 0;
  int components = 0;
  std::vector<double> values;
  const double* at(std::size_t i) const { return values.data() + i * components; }
};

// Reads accessor `index` to doubles: base data from its bufferView (zeros
// when it has none, 3.6.2.3), then sparse substitution (3.6.2.3, "Sparse
// Accessors").
Array read_accessor(const tinygltf::Model& model, int index) {
  const std::string what = "accessors[" + std::to_string(index) + "]";
  if (index < 0 || index >= static_cast<int>(model.accessors.size())) throw InputError(what + " does not exist");
  const tinygltf::Accessor& a = model.accessors[index];
  const ElementLayout layout = element_layout(a.type, a.componentType);
  Array out;
  out.count = a.count;
  out.components = component_count(a.type);
  out.values.assign(a.count * out.components, 0.0);
  if (a.bufferView >= 0)
    read_elements(model, a.bufferView, a.byteOffset, 0, a.count, layout, a.componentType, a.normalized, what,
                  out.values.data());
  if (a.sparse.isSparse) {
    const std::size_t n = static_cast<std::size_t>(a.sparse.count);
    std::vector<double> indices(n), values(n * out.components);
    read_elements(model, a.sparse.indices.bufferView, a.sparse.indices.byteOffset, 0, n,
                  element_layout(TINYGLTF_TYPE_SCALAR, a.sparse.indices.componentType),
                  a.sparse.indices.componentType, false, what + ".sparse.indices", indices.data());
    // Sparse values are tightly packed (no byteStride).
    read_elements(model, a.sparse.values.bufferView, a.sparse.values.byteOffset, layout.size(), n, layout,
                  a.componentType, a.normalized, what + ".sparse.values", values.data());
    for (std::size_t i = 0; i < n; ++i) {
      const auto target = static_cast<std::size_t>(indices[i]);
      if (target >= out.count) throw InputError(what + ".sparse.indices: index out of range");
      std::copy_n(values.data() + i * out.components, out.components, out.values.data() + target * out.components);
    }
  }
  return out;
}

// ---- Node transforms (3.5.3) ------------------------------------------------

// The animatable state of a node: TRS and morph weights.
struct NodeState {
  bool has_matrix = false;
  Mat4 matrix = Mat4::Identity();
  Vec3 translation = Vec3::Zero();
  Quat rotation = Quat::Identity();  // glTF stores [x, y, z, w]
  Vec3 scale = Vec3::Ones();
  std::vector<double> weights;
};

NodeState rest_state(const tinygltf::Model& model, const tinygltf::Node& node) {
  NodeState s;
  if (node.matrix.size() == 16) {  // column-major, like Eigen's default
    s.has_matrix = true;
    for (int i = 0; i < 16; ++i) s.matrix(i % 4, i / 4) = node.matrix[i];
  }
  if (node.translation.size() == 3) s.translation = Vec3(node.translation[0], node.translation[1], node.translation[2]);
  if (node.rotation.size() == 4)
    s.rotation = Quat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
  if (node.scale.size() == 3) s.scale = Vec3(node.scale[0], node.scale[1], node.scale[2]);
  // Morph weights: the node's, else the mesh's defaults (3.7.2.2), else zero.
  if (!node.weights.empty()) {
    s.weights = node.weights;
  } else if (node.mesh >= 0 && node.mesh < static_cast<int>(model.meshes.size())) {
    s.weights = model.meshes[node.mesh].weights;
  }
  return s;
}

// Local matrix: `matrix`, or T * R * S (3.5.3). Quaternions are normalised:
// the spec requires unit rotations, float storage leaves them ~1e-7 off.
Mat4 local_matrix(const NodeState& s) {
  if (s.has_matrix) return s.matrix;
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = s.rotation.normalized().toRotationMatrix() * s.scale.asDiagonal();
  m.topRightCorner<3, 1>() = s.translation;
  return m;
}

// ---- Animation sampling (3.11 and Appendix C) -------------------------------

struct Channel {
  int node = -1;
  std::string path;           // translation, rotation, scale, weights
  std::string interpolation;  // STEP, LINEAR, CUBICSPLINE
  Array input;                // key times, seconds
  Array output;               // values (CUBICSPLINE: in-tangent, value, out-tangent per key)
  int width = 0;              // doubles per value: 3, 4, or the morph target count
};

// Appendix C slerp, shortest path: a = acos(|d|), s = sign(d). The keys are
// normalised first: slerp is defined on unit quaternions, and stored keys are
// not always unit (SimpleSkin's 3-digit keys are 2e-4 off).
Eigen::Vector4d slerp(Eigen::Vector4d a, Eigen::Vector4d b, double t) {
  a.normalize();
  b.normalize();
  double d = a.dot(b);
  if (d < 0.0) {
    b = -b;
    d = -d;
  }
  if (d > 1.0 - 1e-12) return ((1.0 - t) * a + t * b).normalized();  // sin(a) -> 0: the limit is lerp
  const double angle = std::acos(d);
  return (std::sin(angle * (1.0 - t)) * a + std::sin(angle * t) * b) / std::sin(angle);
}

// The channel's value at `time`; clamped to the first/last key outside the
// key range.
std::vector<double> sample(const Channel& c, double time) {
  const std::size_t keys = c.input.count;
  const int w = c.width;
  const bool cubic = c.interpolation == "CUBICSPLINE";
  // Value of key k (for CUBICSPLINE the middle of the tangent/value/tangent triple).
  auto value = [&](std::size_t k) { return c.output.values.data() + (cubic ? 3 * k + 1 : k) * w; };
  std::vector<double> out(w);
  const double* times = c.input.values.data();
  if (time <= times[0] || keys == 1) {
    std::copy_n(value(0), w, out.data());
    return out;
  }
  if (time >= times[keys - 1]) {
    std::copy_n(value(keys - 1), w, out.data());
    return out;
  }
  // k: the last key with t_k <= time < t_(k+1).
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times, times + keys, time) - times) - 1;
  const double td = times[k + 1] - times[k];
  const double t = (time - times[k]) / td;
  const double* v0 = value(k);
  const double* v1 = value(k + 1);
  if (c.interpolation == "STEP") {
    std::copy_n(v0, w, out.data());
  } else if (cubic) {
    // Hermite spline with tangents scaled by the key interval (Appendix C):
    // p = (2t^3-3t^2+1) v_k + td (t^3-2t^2+t) b_k + (-2t^3+3t^2) v_k+1 + td (t^3-t^2) a_k+1
    const double* b0 = v0 + w;      // out-tangent of key k
    const double* a1 = v1 - w;      // in-tangent of key k+1
    const double t2 = t * t, t3 = t2 * t;
    for (int i = 0; i < w; ++i)
      out[i] = (2 * t3 - 3 * t2 + 1) * v0[i] + td * (t3 - 2 * t2 + t) * b0[i] + (-2 * t3 + 3 * t2) * v1[i] +
               td * (t3 - t2) * a1[i];
    if (c.path == "rotation") Eigen::Map<Eigen::Vector4d>(out.data()).normalize();
  } else if (c.path == "rotation") {  // LINEAR rotation: slerp
    Eigen::Map<Eigen::Vector4d>(out.data()) =
        slerp(Eigen::Map<const Eigen::Vector4d>(v0), Eigen::Map<const Eigen::Vector4d>(v1), t);
  } else {  // LINEAR
    for (int i = 0; i < w; ++i) out[i] = (1.0 - t) * v0[i] + t * v1[i];
  }
  return out;
}

std::vector<Channel> read_animation(const tinygltf::Model& model, int index) {
  std::vector<Channel> channels;
  const tinygltf::Animation& anim = model.animations[index];
  for (const tinygltf::AnimationChannel& ch : anim.channels) {
    if (ch.sampler < 0 || ch.sampler >= static_cast<int>(anim.samplers.size()))
      throw InputError("animation channel names a missing sampler");
    if (ch.target_node < 0) continue;  // no target: ignored (3.11)
    if (ch.target_node >= static_cast<int>(model.nodes.size()))
      throw InputError("animation channel targets a missing node");
    const tinygltf::AnimationSampler& s = anim.samplers[ch.sampler];
    Channel c;
    c.node = ch.target_node;
    c.path = ch.target_path;
    c.interpolation = s.interpolation.empty() ? "LINEAR" : s.interpolation;
    if (c.interpolation != "STEP" && c.interpolation != "LINEAR" && c.interpolation != "CUBICSPLINE")
      throw InputError("unknown interpolation " + c.interpolation);
    if (c.path != "translation" && c.path != "rotation" && c.path != "scale" && c.path != "weights") continue;
    c.input = read_accessor(model, s.input);
    c.output = read_accessor(model, s.output);
    const std::size_t per_key = c.interpolation == "CUBICSPLINE" ? 3 : 1;
    if (c.input.count == 0) throw InputError("animation sampler without keys");
    const std::size_t doubles = c.output.count * c.output.components;
    if (doubles % (c.input.count * per_key) != 0) throw InputError("animation sampler output count mismatch");
    c.width = static_cast<int>(doubles / (c.input.count * per_key));
    const int expected = c.path == "rotation" ? 4 : 3;
    if (c.path != "weights" && c.width != expected) throw InputError("animation output has the wrong type for " + c.path);
    channels.push_back(std::move(c));
  }
  return channels;
}

// ---- Scene evaluation -------------------------------------------------------

// The node states at `time` (no animation when channels is empty), then
// world matrices by walking the hierarchy from the roots (3.5.3:
// world = parent world * local).
struct Pose {
  std::vector<NodeState> nodes;
  std::vector<Mat4> world;
};

Pose evaluate(const tinygltf::Model& model, const std::vector<int>& parents, const std::vector<Channel>& channels,
              double time) {
  Pose pose;
  for (const tinygltf::Node& n : model.nodes) pose.nodes.push_back(rest_state(model, n));
  for (const Channel& c : channels) {
    const std::vector<double> v = sample(c, time);
    NodeState& s = pose.nodes[c.node];
    if (c.path == "translation") s.translation = Vec3(v[0], v[1], v[2]);
    if (c.path == "rotation") s.rotation = Quat(v[3], v[0], v[1], v[2]);
    if (c.path == "scale") s.scale = Vec3(v[0], v[1], v[2]);
    if (c.path == "weights") s.weights = v;
  }
  pose.world.assign(model.nodes.size(), Mat4::Identity());
  std::vector<char> done(model.nodes.size(), 0);
  std::function<void(int, const Mat4&)> walk = [&](int n, const Mat4& parent_world) {
    if (done[n]) throw InputError("node " + std::to_string(n) + " has two parents or is on a cycle");
    done[n] = 1;
    pose.world[n] = parent_world * local_matrix(pose.nodes[n]);
    for (int child : model.nodes[n].children) walk(child, pose.world[n]);
  };
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (parents[n] < 0) walk(static_cast<int>(n), Mat4::Identity());
  for (char d : done)
    if (!d) throw InputError("the node hierarchy has a cycle");
  return pose;
}

// One mesh primitive with everything needed to pose it.
struct Primitive {
  int node = -1, mesh = -1, index = -1, skin = -1;
  Array position;
  std::vector<Array> targets;  // morph target POSITION deltas (absent: zeros)
  std::vector<Array> joints, weights;  // JOINTS_n / WEIGHTS_n sets
};

// Morphed positions (3.7.2.2): base + sum_i w_i * delta_i.
std::vector<Vec3> morph(const Primitive& p, const std::vector<double>& weights) {
  std::vector<Vec3> out(p.position.count);
  for (std::size_t v = 0; v < out.size(); ++v) out[v] = Eigen::Map<const Vec3>(p.position.at(v));
  for (std::size_t t = 0; t < p.targets.size() && t < weights.size(); ++t) {
    if (p.targets[t].count == 0 || weights[t] == 0.0) continue;
    for (std::size_t v = 0; v < out.size(); ++v) out[v] += weights[t] * Eigen::Map<const Vec3>(p.targets[t].at(v));
  }
  return out;
}

// World positions of a primitive in `pose`. Skinned (3.7.3): the skinned
// mesh node's own transform is ignored, and
//   p' = sum_i w_i * world(joint_i) * inverseBindMatrix_i * p
// over every JOINTS_n/WEIGHTS_n set. Weights are divided by their sum when
// it is not 1: the spec requires normalised weights, but old COLLADA2GLTF
// exports (CesiumMan, RiggedFigure) cut influences to 4 without rescaling,
// and importers must renormalise to match what viewers show. Unskinned:
// world(node) * p.
std::vector<Vec3> pose_primitive(const tinygltf::Model& model, const Primitive& p, const Pose& pose,
                                 const std::vector<Mat4>& inverse_bind) {
  std::vector<Vec3> points = morph(p, pose.nodes[p.node].weights);
  if (p.skin < 0) {
    const Mat4& m = pose.world[p.node];
    for (Vec3& x : points) x = (m * x.homogeneous()).head<3>();
    return points;
  }
  const std::vector<int>& joints = model.skins[p.skin].joints;
  std::vector<Mat4> joint_matrix(joints.size());
  for (std::size_t j = 0; j < joints.size(); ++j) joint_matrix[j] = pose.world[joints[j]] * inverse_bind[j];
  for (std::size_t v = 0; v < points.size(); ++v) {
    Mat4 m = Mat4::Zero();
    double sum = 0.0;
    for (std::size_t set = 0; set < p.joints.size(); ++set) {
      for (int i = 0; i < 4; ++i) {
        const double w = p.weights[set].at(v)[i];
        if (w == 0.0) continue;
        const double j = p.joints[set].at(v)[i];
        if (j < 0 || j >= static_cast<double>(joints.size()))
          throw InputError("vertex " + std::to_string(v) + " names joint " + std::to_string(j) + " of a skin with " +
                           std::to_string(joints.size()));
        m += w * joint_matrix[static_cast<std::size_t>(j)];
        sum += w;
      }
    }
    if (sum <= 0.0) throw InputError("vertex " + std::to_string(v) + " of a skinned primitive has no weight");
    points[v] = (m / sum * points[v].homogeneous()).head<3>();
  }
  return points;
}

// ---- Command line -----------------------------------------------------------

bool no_image_loader(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
                     void*) {
  return true;  // images do not move vertices
}

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

int usage(const char* message) {
  std::fprintf(stderr,
               "gltf_reference: %s\nusage: gltf_reference FILE.glb|FILE.gltf [--times t1,t2,...] "
               "[--animation INDEX|none] [-o OUT.json]\n",
               message);
  return 2;
}

// Over 150 lines: the oracle follows the glTF specification's skinning
// formulas in their order (sample, local, world, joint matrices, skin),
// with no rigel code, so that it reads against the specification.
// Without --animation the first animation plays, when the file has one.
int run(const std::string& file, const std::vector<double>& times, int animation, bool animation_given,
        const std::string& out_path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(no_image_loader, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = file.size() >= 4 && file.compare(file.size() - 4, 4, ".glb") == 0;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, file)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, file);
  while (!err.empty() && std::isspace(static_cast<unsigned char>(err.back()))) err.pop_back();
  if (!ok) throw InputError("cannot load " + file + ": " + err);
  if (!animation_given && model.animations.empty()) animation = -1;
  if (animation >= static_cast<int>(model.animations.size()))
    throw InputError("animation " + std::to_string(animation) + " does not exist (the file has " +
                     std::to_string(model.animations.size()) + ")");

  // Parents from the children lists; roots have none.
  std::vector<int> parents(model.nodes.size(), -1);
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    for (int child : model.nodes[n].children) {
      if (child < 0 || child >= static_cast<int>(model.nodes.size()) || parents[child] >= 0)
        throw InputError("nodes[" + std::to_string(n) + "] has a bad or shared child " + std::to_string(child));
      parents[child] = static_cast<int>(n);
    }
  // Nodes of the displayed scene (3.5.2): the default scene, else scene 0,
  // else every root.
  std::vector<char> in_scene(model.nodes.size(), 0);
  std::function<void(int)> mark = [&](int n) {
    in_scene[n] = 1;
    for (int c : model.nodes[n].children) mark(c);
  };
  const int scene = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
  if (scene >= static_cast<int>(model.scenes.size())) throw InputError("the default scene does not exist");
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (scene < 0 && parents[n] < 0) mark(static_cast<int>(n));
  if (scene >= 0)
    for (int n : model.scenes[scene].nodes) {
      if (n < 0 || n >= static_cast<int>(model.nodes.size()) || parents[n] >= 0)
        throw InputError("scene lists a missing or non-root node " + std::to_string(n));
      mark(n);
    }

  // Inverse bind matrices per skin (identity when absent, 3.7.3.1).
  std::vector<std::vector<Mat4>> inverse_bind(model.skins.size());
  for (std::size_t s = 0; s < model.skins.size(); ++s) {
    const tinygltf::Skin& skin = model.skins[s];
    for (int j : skin.joints)
      if (j < 0 || j >= static_cast<int>(model.nodes.size())) throw InputError("skin joint is not a node");
    inverse_bind[s].assign(skin.joints.size(), Mat4::Identity());
    if (skin.inverseBindMatrices >= 0) {
      const Array ibm = read_accessor(model, skin.inverseBindMatrices);
      if (ibm.components != 16 || ibm.count < skin.joints.size())
        throw InputError("skins[" + std::to_string(s) + "].inverseBindMatrices is not one MAT4 per joint");
      for (std::size_t j = 0; j < skin.joints.size(); ++j) inverse_bind[s][j] = Eigen::Map<const Mat4>(ibm.at(j));
    }
  }

  std::vector<Primitive> prims;
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const tinygltf::Node& node = model.nodes[n];
    if (!in_scene[n] || node.mesh < 0) continue;
    if (node.mesh >= static_cast<int>(model.meshes.size())) throw InputError("node names a missing mesh");
    if (node.skin >= static_cast<int>(model.skins.size())) throw InputError("node names a missing skin");
    const tinygltf::Mesh& mesh = model.meshes[node.mesh];
    for (std::size_t i = 0; i < mesh.primitives.size(); ++i) {
      const tinygltf::Primitive& src = mesh.primitives[i];
      const auto pos = src.attributes.find("POSITION");
      if (pos == src.attributes.end()) continue;  // nothing to place
      Primitive p;
      p.node = static_cast<int>(n);
      p.mesh = node.mesh;
      p.index = static_cast<int>(i);
      p.position = read_accessor(model, pos->second);
      if (p.position.components != 3) throw InputError("POSITION is not VEC3");
      for (const auto& target : src.targets) {
        const auto d = target.find("POSITION");
        p.targets.push_back(d == target.end() ? Array{} : read_accessor(model, d->second));
        if (p.targets.back().count != 0 && p.targets.back().count != p.position.count)
          throw InputError("morph target POSITION count differs from the base");
      }
      for (int set = 0;; ++set) {
        const auto j = src.attributes.find("JOINTS_" + std::to_string(set));
        const auto w = src.attributes.find("WEIGHTS_" + std::to_string(set));
        if (j == src.attributes.end() || w == src.attributes.end()) break;
        p.joints.push_back(read_accessor(model, j->second));
        p.weights.push_back(read_accessor(model, w->second));
        if (p.joints.back().count != p.position.count || p.weights.back().count != p.position.count ||
            p.joints.back().components != 4 || p.weights.back().components != 4)
          throw InputError("JOINTS_/WEIGHTS_" + std::to_string(set) + " do not match POSITION");
      }
      if (node.skin >= 0 && !p.joints.empty()) p.skin = node.skin;
      prims.push_back(std::move(p));
    }
  }

  // The model's size: bounding boxes of all positions in the rest pose
  // (no animation; skinned per 3.7.3 like every other pose) and in the bind
  // pose (world(joint) * IBM = identity: POSITION itself for skinned
  // primitives). They differ when the joints' rest transforms are not the
  // inverses of the IBMs: assimp_quad_skin.glb's rest pose is 100x its
  // bind-space positions, so the rest-pose box is the size seen in the scene.
  struct Box {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    void add(const Vec3& x) { lo = lo.cwiseMin(x), hi = hi.cwiseMax(x); }
    double diagonal() const { return std::isfinite(lo.x()) ? (hi - lo).norm() : 0.0; }
  } rest_box, bind_box;
  {
    const Pose rest = evaluate(model, parents, {}, 0.0);
    for (const Primitive& p : prims) {
      for (const Vec3& x : pose_primitive(model, p, rest, p.skin >= 0 ? inverse_bind[p.skin] : std::vector<Mat4>{}))
        rest_box.add(x);
      for (const Vec3& x : morph(p, rest.nodes[p.node].weights))
        bind_box.add(p.skin >= 0 ? x : (rest.world[p.node] * x.homogeneous()).head<3>());
    }
  }

  const std::vector<Channel> channels = animation >= 0 ? read_animation(model, animation) : std::vector<Channel>{};
  std::vector<std::vector<std::vector<Vec3>>> positions(prims.size());  // [prim][time][vertex]
  for (double t : times) {
    const Pose pose = evaluate(model, parents, channels, t);
    for (std::size_t i = 0; i < prims.size(); ++i)
      positions[i].push_back(pose_primitive(model, prims[i], pose, prims[i].skin >= 0 ? inverse_bind[prims[i].skin]
                                                                                       : std::vector<Mat4>{}));
  }

  std::FILE* out = out_path.empty() || out_path == "-" ? stdout : std::fopen(out_path.c_str(), "w");
  if (!out) throw InputError("cannot write " + out_path);
  std::fprintf(out, "{\"file\": %s, \"animation\": %d, ", json_string(file).c_str(), animation);
  if (!channels.empty()) {  // first and last key time over the animation's channels
    double start = std::numeric_limits<double>::infinity(), end = -start;
    for (const Channel& c : channels) {
      start = std::min(start, c.input.values.front());
      end = std::max(end, c.input.values.back());
    }
    std::fprintf(out, "\"animation_range\": [%.17g, %.17g], ", start, end);
  }
  std::fprintf(out, "\"times\": [");
  for (std::size_t i = 0; i < times.size(); ++i) std::fprintf(out, "%s%.17g", i ? ", " : "", times[i]);
  std::fprintf(out, "],\n\"primitives\": [");
  for (std::size_t i = 0; i < prims.size(); ++i) {
    const Primitive& p = prims[i];
    std::fprintf(out,
                 "%s\n{\"node\": %d, \"node_name\": %s, \"mesh\": %d, \"mesh_name\": %s, \"primitive\": %d, "
                 "\"skinned\": %s, \"vertex_count\": %zu, \"positions\": [",
                 i ? "," : "", p.node, json_string(model.nodes[p.node].name).c_str(), p.mesh,
                 json_string(model.meshes[p.mesh].name).c_str(), p.index, p.skin >= 0 ? "true" : "false",
                 p.position.count);
    for (std::size_t t = 0; t < positions[i].size(); ++t) {
      std::fprintf(out, "%s\n[", t ? "," : "");
      for (std::size_t v = 0; v < positions[i][t].size(); ++v) {
        const Vec3& x = positions[i][t][v];
        std::fprintf(out, "%s%.17g, %.17g, %.17g", v ? ", " : "", x.x(), x.y(), x.z());
      }
      std::fprintf(out, "]");
    }
    std::fprintf(out, "]}");
  }
  std::fprintf(out, "],\n\"bounds_diagonal\": %.17g, \"bind_bounds_diagonal\": %.17g}\n", rest_box.diagonal(),
               bind_box.diagonal());
  const bool write_failed = std::ferror(out) != 0;
  if (out != stdout && std::fclose(out) != 0) throw InputError("cannot write " + out_path);
  if (write_failed) throw InputError("cannot write " + out_path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string file, out_path;
  std::vector<double> times{0.0};
  int animation = 0;
  bool animation_given = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--times" && has_value) {
      times.clear();
      std::string list = argv[++i];
      for (std::size_t start = 0; start <= list.size();) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const std::string item = list.substr(start, comma - start);
        char* end = nullptr;
        const double t = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || !std::isfinite(t)) return usage(("bad time '" + item + "'").c_str());
        times.push_back(t);
        start = comma + 1;
      }
    } else if (arg == "--animation" && has_value) {
      const std::string v = argv[++i];
      char* end = nullptr;
      const long a = std::strtol(v.c_str(), &end, 10);
      if (v == "none") {
        animation = -1;
      } else if (v.empty() || *end != '\0' || a < 0 || a > std::numeric_limits<int>::max()) {
        return usage(("bad animation index '" + v + "'").c_str());
      } else {
        animation = static_cast<int>(a);
      }
      animation_given = true;
    } else if (arg == "-o" && has_value) {
      out_path = argv[++i];
    } else if (!arg.empty() && arg[0] != '-' && file.empty()) {
      file = arg;
    } else {
      return usage(("unexpected argument '" + arg + "'").c_str());
    }
  }
  if (file.empty()) return usage("no input file");
  try {
    return run(file, times, animation, animation_given, out_path);
  } catch (const InputError& e) {
    std::fprintf(stderr, "gltf_reference: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gltf_reference: %s: %s\n", file.c_str(), e.what());
    return 1;
  }
}
