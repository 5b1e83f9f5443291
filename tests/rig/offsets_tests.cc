// Guide offsets (docs/RIG.md): a guide with a joint and a translate/rotate
// places its control off the joint. Every component type that makes a
// control at a guide puts it there, and its joints keep their rest pose
// while the controls are zeroed (in FK and IK for a limb); the types that
// cannot honour an offset refuse it in validate().
#include <gtest/gtest.h>

#include <string>

#include "rig_test_util.h"
#include "rigel/math/rotation.h"
#include "rigel/math/transform.h"
#include "rigel/ops/util/blend.h"
#include "rigel/rig/components/limbs.h"
#include "rigel/rig/definition_io.h"

namespace rigel::rig {
namespace {

using graph::NodeId;
using math::Mat4;
using math::Vec3;
using testing::pose_error;

const Vec3 kTranslate(0.03, 0.1, -0.02);
const Vec3 kRotate(20, -10, 35);

Mat4 offset() {
  math::TransformParts parts;
  parts.translate = kTranslate;
  parts.rotate = math::to_radians(kRotate);
  return math::compose(parts);
}

std::string guide(const std::string& joint, bool offset_it, const std::string& name = "") {
  std::string out = "<guide";
  if (!name.empty()) out += " name=\"" + name + "\"";
  out += " joint=\"" + joint + "\"";
  if (offset_it) out += " translate=\"0.03 0.1 -0.02\" rotate=\"20 -10 35\"";
  return out + "/>";
}

Definition one_component(const std::string& type, const std::string& guides, const std::string& params = "") {
  const std::string text = "<rig name=\"hero\" version=\"1.0\"><component type=\"" + type +
                           "\" name=\"part\" side=\"L\" version=\"1.0\" rigId=\"8e81973e-0bec-47b0-b898-d190f9ebdacc\">" +
                           guides + params + "</component></rig>";
  ParseResult p = parse_definition(text, Syntax::kXml, "offsets.rig.xml");
  EXPECT_TRUE(p.ok()) << (p.ok() ? "" : p.errors.front().str());
  const std::vector<Diagnostic> problems = validate(p.definition);
  EXPECT_TRUE(problems.empty()) << (problems.empty() ? "" : problems.front().str());
  return p.definition;
}

struct Case {
  std::string type, guides, params;
  std::string control;  // address of the control of the offset guide
  std::string joint;    // that guide's joint
  double within = 1e-9;  // how near the guide it stands
};

TEST(GuideOffsets, controls_stand_at_the_offset_and_joints_keep_their_rest) {
  const Case cases[] = {
      {"fkChain", guide("upper_arm.L", false) + guide("forearm.L", true) + guide("hand.L", false), "",
       "hero:part_L/fk[1]", "forearm.L"},
      {"limb", guide("upper_arm.L", false, "upper") + guide("forearm.L", true, "lower") + guide("hand.L", false, "end"),
       "", "hero:part_L/fk[1]", "forearm.L"},
      {"limb", guide("upper_arm.L", false, "upper") + guide("forearm.L", false, "lower") + guide("hand.L", true, "end"),
       "", "hero:part_L/ik", "hand.L"},
      {"limb", guide("upper_arm.L", true, "upper") + guide("forearm.L", false, "lower") + guide("hand.L", true, "end"),
       "<param name=\"defaultMode\" value=\"ik\"/>", "hero:part_L/fk[0]", "upper_arm.L"},
      {"ikChain", guide("upper_arm.L", false) + guide("forearm.L", false) + guide("hand.L", true), "", "hero:part_L/ik",
       "hand.L"},
      {"simple", guide("breast.L", true), "", "hero:part_L/main[0]", "breast.L"},
      {"hip", guide("spine", true), "", "hero:part_L/main", "spine"},
      {"hand", guide("hand.L", true) + guide("f_index.01.L", false, "index.0") + guide("f_index.02.L", true, "index.1"),
       "", "hero:part_L/hand", "hand.L"},
      {"hand", guide("hand.L", false) + guide("f_index.01.L", false, "index.0") + guide("f_index.02.L", true, "index.1"),
       "", "hero:part_L/finger[1]", "f_index.02.L"},
      {"spine", guide("spine.001", false) + guide("spine.002", true) + guide("spine.003", false), "",
       "hero:part_L/fk[1]", "spine.002"},
      {"spine", guide("spine.001", false) + guide("spine.002", true) + guide("spine.003", false),
       "<param name=\"kinematicType\" value=\"splineIK\"/>", "hero:part_L/fk[1]", "spine.002"},
      {"neck", guide("spine.004", true) + guide("spine.005", false) + guide("spine.006", false), "",
       "hero:part_L/neck[0]", "spine.004"},
      // The eye's hook is an orthonormal frame; the float32 joint's is not quite.
      {"eye", guide("eye.L", true), "", "hero:part_L/hook[0]", "eye.L", 1e-6},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.type + " " + c.control);
    testing::BuiltRig r = testing::built_rig(one_component(c.type, c.guides, c.params));
    ASSERT_TRUE(r.build);
    const NodeId control = testing::at(*r.scene, c.control);
    ASSERT_TRUE(control.is_valid());
    // Limb controls stand at the guide's rigid part (limbs.cc); the
    // float32 joints' frames carry scales of 1 +- 3e-6.
    const bool rigid = c.type == "limb" || c.type == "ikChain";
    const Mat4 expected = rigid ? math::rigid_part(r.rest.at(c.joint) * offset()) : Mat4(r.rest.at(c.joint) * offset());
    EXPECT_LE((r.scene->world_matrix(control) - expected).cwiseAbs().maxCoeff(), c.within) << "the control is at the guide";
    std::string worst;
    EXPECT_LE(pose_error(*r.scene, r.rest, &worst), 1e-9) << "joints at rest (worst: " << worst << ")";
    if (c.type == "limb") {
      // The other mode too, and matching both ways keeps the rest pose.
      graph::Graph& g = r.g();
      const NodeId sw = testing::at(*r.scene, "hero:part_L/fkIkSwitch");
      const double mode = std::get<double>(g.node(sw)->value(ops::util::fk_ik_attr::kFkIk));
      ASSERT_TRUE(g.set_value(graph::Plug{sw, ops::util::fk_ik_attr::kFkIk, -1}, graph::Value(1.0 - mode)).is_ok());
      EXPECT_LE(pose_error(*r.scene, r.rest, &worst), 1e-7) << "the other mode at rest (worst: " << worst << ")";
      const NodeId meta = testing::at(*r.scene, "hero:part_L");
      ASSERT_TRUE(components::match_fk_to_ik(*r.scene, meta).is_ok());
      ASSERT_TRUE(components::match_ik_to_fk(*r.scene, meta).is_ok());
      for (double m : {0.0, 1.0}) {
        ASSERT_TRUE(g.set_value(graph::Plug{sw, ops::util::fk_ik_attr::kFkIk, -1}, graph::Value(m)).is_ok());
        EXPECT_LE(pose_error(*r.scene, r.rest, &worst), 1e-7) << "matched, mode " << m << " (worst: " << worst << ")";
      }
    }
  }
}

TEST(GuideOffsets, types_that_cannot_honour_an_offset_refuse_it) {
  const std::string text =
      "<rig name=\"hero\" version=\"1.0\">"
      "<component type=\"twist\" name=\"tw\" side=\"L\" version=\"1.0\" rigId=\"6b4cb242-4a23-4596-a217-beaddbc496cb\">"
      "<guide name=\"start\" joint=\"upper_arm.L\" translate=\"0 0.1 0\"/><guide name=\"end\" joint=\"forearm.L\"/></component>"
      "<component type=\"foot\" name=\"foot\" side=\"L\" version=\"1.0\" rigId=\"92276658-1e27-41c0-8a6a-63ec24ede6a4\">"
      "<guide name=\"ankle\" joint=\"foot.L\" rotate=\"0 10 0\"/><guide name=\"ball\" joint=\"toe.L\"/>"
      "<guide name=\"toe\" translate=\"0.098 0 0.17\"/><guide name=\"heel\" joint=\"heel.02.L\" translate=\"0 0 -0.01\"/>"
      "<guide name=\"inner\" translate=\"0.05 0 0.05\"/><guide name=\"outer\" translate=\"0.145 0 0.05\"/></component>"
      "</rig>";
  ParseResult p = parse_definition(text, Syntax::kXml, "o.rig.xml");
  ASSERT_TRUE(p.ok()) << p.errors.front().str();
  std::vector<std::string> messages;
  for (const Diagnostic& d : validate(p.definition)) messages.push_back(d.message);
  ASSERT_EQ(messages.size(), 2u) << (messages.empty() ? "" : messages.front());
  EXPECT_NE(messages[0].find("guide 0 (upper_arm.L) takes no offset"), std::string::npos) << messages[0];
  EXPECT_NE(messages[1].find("guide 0 (foot.L) takes no offset"), std::string::npos) << messages[1];
}

}  // namespace
}  // namespace rigel::rig
