// glTF node hierarchy (gltf_internal.h: place_instances). Section numbers refer to the glTF 2.0
// specification (registry.khronos.org/glTF/specs/2.0/glTF-2.0.html).
#include <tiny_gltf.h>

#include <cmath>
#include <string>

#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gltf_internal.h"
#include "penumbra/assets/load_error.h"

namespace penumbra::assets::detail {
namespace {

class Placer {
 public:
  Placer(const tinygltf::Model& m, const std::string& name, Model& out)
      : m_(m), name_(name), out_(out) {}

  glm::mat4 local_matrix(std::size_t i) const {
    const tinygltf::Node& n = m_.nodes[i];
    const std::string where = "node " + std::to_string(i) + ": ";
    auto finite = [&](const std::vector<double>& v, std::size_t size, const char* what) {
      if (!v.empty() && v.size() != size)
        fail(where + what + " needs " + std::to_string(size) + " numbers");
      for (double d : v)
        if (!std::isfinite(d)) fail(where + what + " is not finite");
      return !v.empty();
    };
    glm::mat4 m(1.0f);
    if (finite(n.matrix, 16, "matrix")) {  // column-major (section 3.5.3)
      for (int k = 0; k < 16; ++k)
        glm::value_ptr(m)[k] = static_cast<float>(n.matrix[static_cast<std::size_t>(k)]);
      return m;
    }
    glm::vec3 t(0.0f), s(1.0f);
    glm::quat r(1.0f, 0.0f, 0.0f, 0.0f);
    if (finite(n.translation, 3, "translation"))
      t = {n.translation[0], n.translation[1], n.translation[2]};
    if (finite(n.scale, 3, "scale")) s = {n.scale[0], n.scale[1], n.scale[2]};
    if (finite(n.rotation, 4, "rotation")) {  // (x, y, z, w)
      r = glm::quat(static_cast<float>(n.rotation[3]), static_cast<float>(n.rotation[0]),
                    static_cast<float>(n.rotation[1]), static_cast<float>(n.rotation[2]));
      const float len = glm::length(r);
      if (!(len > 1e-6f)) fail(where + "rotation quaternion has zero length");
      r /= len;
    }
    // T * R * S (section 3.5.3).
    m = glm::mat4_cast(r);
    for (int c = 0; c < 3; ++c) m[c] *= s[c];
    m[3] = glm::vec4(t, 1.0f);
    return m;
  }

  // The node graph must be a forest (section 3.5.1): children in range, one parent, no cycles.
  std::vector<int> parents() const {
    const std::size_t n = m_.nodes.size();
    std::vector<int> parent(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
      for (int c : m_.nodes[i].children) {
        if (c < 0 || static_cast<std::size_t>(c) >= n)
          fail("node " + std::to_string(i) + ": child " + std::to_string(c) + " out of range");
        if (parent[static_cast<std::size_t>(c)] != -1)
          fail("node " + std::to_string(c) + " is a child of both node " +
               std::to_string(parent[static_cast<std::size_t>(c)]) + " and node " +
               std::to_string(i));
        parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
      }
    }
    // With one parent each, a cycle is a parent chain that returns to a node of the same walk;
    // a walk stops at nodes an earlier walk has cleared.
    std::vector<std::size_t> walk(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      int j = static_cast<int>(i);
      while (j != -1 && walk[static_cast<std::size_t>(j)] == 0) {
        walk[static_cast<std::size_t>(j)] = i + 1;
        j = parent[static_cast<std::size_t>(j)];
      }
      if (j != -1 && walk[static_cast<std::size_t>(j)] == i + 1)
        fail("recursive node graph: node " + std::to_string(j) + " is its own ancestor");
    }
    return parent;
  }

  void place_instances(const MeshRanges& ranges) {
    const std::vector<int> parent = parents();
    std::vector<int> roots;
    if (m_.defaultScene >= 0 || !m_.scenes.empty()) {
      const int s = m_.defaultScene >= 0 ? m_.defaultScene : 0;
      if (static_cast<std::size_t>(s) >= m_.scenes.size())
        fail("scene " + std::to_string(s) + " out of range");
      roots = m_.scenes[static_cast<std::size_t>(s)].nodes;
    } else {
      for (std::size_t i = 0; i < parent.size(); ++i)
        if (parent[i] == -1) roots.push_back(static_cast<int>(i));
      if (!roots.empty()) out_.warnings.push_back("no scene; placing every root node");
    }
    std::vector<char> seen(m_.nodes.size(), 0);
    std::vector<std::pair<int, glm::mat4>> stack;
    for (int r : roots) {
      if (r < 0 || static_cast<std::size_t>(r) >= m_.nodes.size())
        fail("scene node " + std::to_string(r) + " out of range");
      if (parent[static_cast<std::size_t>(r)] != -1)
        fail("scene node " + std::to_string(r) + " is not a root node");
      if (seen[static_cast<std::size_t>(r)]++)
        fail("scene lists node " + std::to_string(r) + " twice");
    }
    // Depth-first, in document order: instances come out in scene order, parents first.
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, gltf_to_engine());
    while (!stack.empty()) {
      const auto [i, parent_world] = stack.back();
      stack.pop_back();
      const tinygltf::Node& node = m_.nodes[static_cast<std::size_t>(i)];
      const glm::mat4 world = parent_world * local_matrix(static_cast<std::size_t>(i));
      if (node.mesh >= 0) {
        if (static_cast<std::size_t>(node.mesh) >= ranges.size())
          fail("node " + std::to_string(i) + ": mesh " + std::to_string(node.mesh) +
               " out of range");
        const auto [first, end] = ranges[static_cast<std::size_t>(node.mesh)];
        for (std::size_t k = first; k < end; ++k)
          out_.instances.push_back({static_cast<std::uint32_t>(k), i, world});
      }
      for (auto c = node.children.rbegin(); c != node.children.rend(); ++c)
        stack.emplace_back(*c, world);
    }
  }

 private:
  [[noreturn]] void fail(const std::string& reason) const { throw LoadError(name_, reason); }

  const tinygltf::Model& m_;
  const std::string& name_;
  Model& out_;
};

}  // namespace

void place_instances(const tinygltf::Model& model, const MeshRanges& ranges,
                     const std::string& name, Model& out) {
  Placer(model, name, out).place_instances(ranges);
}

}  // namespace penumbra::assets::detail
