// The schemas of the component types rigel ships: the contract between
// definition files and the component classes (components/*.cc implement
// the steps; the `ephemeral` class lives in the ephemeral layer). docs/RIG.md
// lists them for people; `rigel components` prints them.
#include <cstdio>

#include <nlohmann/json.hpp>

#include "rigel/rig/schema.h"

namespace rigel::rig {
namespace {

ParamSpec p_bool(std::string name, bool value, std::string help) {
  return ParamSpec{std::move(name), ParamType::kBool, value, {}, {}, {}, std::move(help)};
}
ParamSpec p_int(std::string name, std::int64_t value, double min, double max, std::string help) {
  return ParamSpec{std::move(name), ParamType::kInt, value, min, max, {}, std::move(help)};
}
ParamSpec p_double(std::string name, double value, std::optional<double> min, std::optional<double> max,
                   std::string help) {
  return ParamSpec{std::move(name), ParamType::kDouble, value, min, max, {}, std::move(help)};
}
ParamSpec p_string(std::string name, std::string value, std::string help) {
  return ParamSpec{std::move(name), ParamType::kString, std::move(value), {}, {}, {}, std::move(help)};
}
ParamSpec p_vec3(std::string name, math::Vec3 value, std::string help) {
  return ParamSpec{std::move(name), ParamType::kVec3, value, {}, {}, {}, std::move(help)};
}
ParamSpec p_enum(std::string name, std::string value, std::vector<std::string> choices, std::string help) {
  return ParamSpec{std::move(name), ParamType::kEnum, std::move(value), {}, {}, std::move(choices), std::move(help)};
}

// A call's own checks: a function id, and args that are a JSON object.
std::vector<std::string> check_call(const Component& component) {
  std::vector<std::string> problems;
  const Param* fn = component.param("function");
  if (!fn || !std::holds_alternative<std::string>(fn->value) || std::get<std::string>(fn->value).empty())
    problems.emplace_back("a call needs the id of its build function (parameter 'function')");
  const Param* args = component.param("args");
  if (args && std::holds_alternative<std::string>(args->value)) {
    const auto parsed = nlohmann::json::parse(std::get<std::string>(args->value), nullptr, false);
    if (!parsed.is_object()) problems.emplace_back("parameter 'args' must be a JSON object");
  }
  return problems;
}

// Over 150 lines: a table, one entry per component type (parameters, guides,
// controls, hooks, features), read as data; splitting it would only scatter it.
std::vector<ComponentSchema> make_schemas() {
  std::vector<ComponentSchema> s;

  {
    ComponentSchema c;
    c.type = "global";
    c.help = "The rig's root: one control that moves, turns and scales the whole rig (no joint).";
    c.guides = {1, 1, {"main"}, "Where the global control sits (usually the origin)."};
    c.controls = {{"main", "fourArrowCircle", "yellow", 1.0, "The global control."}};
    c.hooks = {"main"};
    c.root_only = true;
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "hip";
    c.help = "Centre of gravity: one control driving the hip joint; the body hangs from it.";
    c.guides = {1, 1, {"hip"}, "The hip joint."};
    c.controls = {{"main", "circle", "yellow", 0.6, "The hip (COG) control."}};
    c.hooks = {"hip"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "spine";
    c.help = "A spine of 3 or more joints: FK, spline IK, or stretchy spline IK with a shoulder control.";
    c.params = {p_enum("kinematicType", "fk", {"fk", "splineIK", "stretchySplineIK"},
                       "How the joints are driven (seed 002's KinematicType).")};
    c.guides = {3, -1, {}, "The spine joints, hips end first."};
    c.controls = {{"fk", "circle", "yellow", 0.5, "One FK control per joint."},
                  {"shoulder", "cube", "orange", 0.3, "The spline IK's end (splineIK, stretchySplineIK)."},
                  {"mid", "circle", "orange", 0.4,
                   "The spline's middle; follows halfway between the base and the shoulder (splineIK, "
                   "stretchySplineIK)."}};
    c.hooks = {"guide[i]"};
    c.features = {"stretch"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "neck";
    c.help = "Neck joints and the head: FK with a head control that can keep its world orientation.";
    c.params = {p_enum("headOrient", "local", {"local", "world"},
                       "local: the head follows the neck; world: it keeps its orientation in the world.")};
    c.guides = {2, -1, {}, "The neck joints, then the head joint last."};
    c.controls = {{"neck", "circle", "yellow", 0.3, "One control per neck joint."},
                  {"head", "circle", "yellow", 0.4, "The head control."}};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "fkChain";
    c.help = "A chain of joints, one FK control each.";
    c.guides = {1, -1, {}, "The joints, root first."};
    c.controls = {{"fk", "circle", "yellow", 0.3, "One FK control per joint."}};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "ikChain";
    c.help = "A chain of 2 or more joints solved by IK toward an IK control, with a pole control.";
    c.params = {p_enum("solver", "auto", {"auto", "twoBone", "fabrik", "ccd"},
                       "auto: two-bone for 3 joints, FABRIK beyond."),
                p_bool("stretch", false, "Joints stretch to reach the IK control (two-bone)."),
                p_double("poleDistance", 0.5, 0.0, {}, "Distance of the pole control from the middle joint, m.")};
    c.guides = {2, -1, {}, "The joints, root first."};
    c.controls = {{"ik", "cube", "red", 0.2, "The IK target."}, {"pole", "diamond", "red", 0.1, "The pole vector."}};
    c.hooks = {"guide[i]"};
    c.features = {"stretch"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "limb";
    c.help = "An arm or leg of three joints: FK and IK with a switch matching both ways, pole vector, stretch.";
    c.params = {p_enum("kind", "arm", {"arm", "leg"}, "Arm or leg: sets default shapes and pole direction."),
                p_enum("defaultMode", "fk", {"fk", "ik"}, "The mode the switch starts in."),
                p_bool("stretch", true, "IK stretches past full extension."),
                p_double("maxStretch", 1.5, 1.0, {}, "Largest stretch factor."),
                p_double("poleDistance", 0.5, 0.0, {}, "Distance of the pole control from the middle joint, m."),
                p_string("ikSpaces", "",
                         "The IK control's spaces besides its parent: `world` or NAME=COMPONENT/ROLE (a component's "
                         "name, else its type, and a control role), comma-separated; spaces whose component the rig "
                         "lacks are left out. Empty: world,global=global/main,chest=chest/main,head=neck/head for "
                         "an arm, world,global=global/main,hip=hip/main for a leg.")};
    c.guides = {3, 3, {"upper", "lower", "end"}, "Shoulder/hip, elbow/knee, wrist/ankle."};
    c.controls = {{"fk", "circle", "yellow", 0.25, "FK controls, one per joint."},
                  {"ik", "cube", "red", 0.15, "IK control at the end joint."},
                  {"pole", "diamond", "red", 0.08, "Pole vector control."},
                  {"switch", "cross", "green", 0.1, "Holds fkIk (0 = FK, 1 = IK)."}};
    c.hooks = {"upper", "lower", "end"};
    c.features = {"ik", "stretch"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "quadLeg";
    c.help = "A quadruped's leg of three segments and the foot (upper, lower, hock, foot): FK, IK with a spring or "
             "pinned hock angle, a switch matching both ways, pole vector, stretch.";
    c.params = {p_enum("kind", "hind", {"hind", "front"}, "Hind or front leg: the pole's side for a straight leg."),
                p_enum("hockMode", "spring", {"spring", "pinned"},
                       "spring: the hock bone keeps its angle to the upper bone as the leg bends; pinned: a hock "
                       "control under the IK control sets it."),
                p_enum("defaultMode", "ik", {"fk", "ik"}, "The mode the switch starts in."),
                p_bool("stretch", false, "IK stretches past full extension."),
                p_double("maxStretch", 1.2, 1.0, {}, "Largest stretch factor."),
                p_double("poleDistance", 0.4, 0.0, {}, "Distance of the pole control from the knee, m."),
                p_string("ikSpaces", "",
                         "The IK control's spaces besides its parent (as limb's); empty: "
                         "world,global=global/main,hip=hip/main."),
                p_string("ikSpace", "global",
                         "The space the IK control starts in, so the feet stay planted as the body moves: parent, "
                         "world or a name of ikSpaces (one the rig lacks: world).")};
    c.guides = {4, 4, {"upper", "lower", "hock", "foot"},
                "Hip/shoulder, knee/elbow, hock/knee and fetlock/paw joints, each the child of the one before."};
    c.controls = {{"fk", "circle", "yellow", 0.2, "FK controls, one per joint."},
                  {"ik", "cube", "red", 0.15, "IK control at the foot joint."},
                  {"hock", "circle", "red", 0.12, "Turns the hock bone about the foot (pinned)."},
                  {"pole", "diamond", "red", 0.08, "Pole vector control."},
                  {"switch", "cross", "green", 0.1, "Holds fkIk (0 = FK, 1 = IK)."}};
    c.hooks = {"upper", "lower", "hock", "foot"};
    c.features = {"ik", "stretch"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "springChain";
    c.help = "A chain with secondary motion: FK controls set its goal pose, and its joints follow that pose on "
             "damped springs stepped per frame (deterministic, bakeable).";
    c.params = {p_double("stiffness", 100.0, 0.0, {}, "The springs' pull toward the goal pose, 1/s^2."),
                p_double("damping", 10.0, 0.0, {}, "How fast the motion dies down, 1/s."),
                p_double("gravity", 0.0, {}, {}, "Pull down the world's y axis, m/s^2 (9.81: earth's)."),
                p_double("startFrame", 0.0, {}, {}, "The frame the chain rests on its goal pose at (and before)."),
                p_double("weight", 1.0, 0.0, 1.0,
                         "The fkIkSwitch's starting fkIk: 0 the FK pose, 1 the spring's (keyable on the switch).")};
    c.guides = {2, -1, {}, "The joints, root first, each the child of the one before."};
    c.controls = {{"fk", "circle", "green", 0.2, "One FK control per joint: the goal pose."}};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "foot";
    c.help = "Reverse foot: heel, ball and toe roll, bank, heel/toe/ball twist and toe tap (a reverseFoot node the "
             "foot control stands for); takes over the IK end of a parent limb.";
    c.params = {p_double("rollBreak", 30.0, 0.0, 90.0, "Roll angle (degrees) where the ball stops and the toe lifts.")};
    c.guides = {6, 6, {"ankle", "ball", "toe", "heel", "inner", "outer"},
                "Ankle and ball joints (the ball a child of the ankle); toe tip, heel, inner and outer edge of the "
                "sole: pivots, joints or values (positions only)."};
    c.controls = {{"foot", "square", "red", 0.3,
                   "On the ground below the ankle, under the parent limb's ik control; moves the foot and stands for "
                   "the reverseFoot node's roll, bank, twists and toeTap."},
                  {"toeFk", "circle", "yellow", 0.1, "FK control of the ball joint (with a parent limb)."}};
    c.hooks = {"ankle", "ball", "toe"};
    c.fixed_guides = 2;  // the ankle and ball joints: the reverse foot turns them in place
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "hand";
    c.help = "A hand control with FK fingers; keyable curl (all fingers and per finger) and spread turn every finger.";
    c.params = {p_bool("curlAttributes", true,
                       "Make the fingerCurl node: keyable curl, fingerCurl[k] and spread, layered under the "
                       "finger controls."),
                p_enum("bendAxis", "x", {"x", "y", "z", "-x", "-y", "-z"},
                       "Each finger's first-joint axis it curls about (glTF from Blender: x); a bent finger curls "
                       "about its own plane's normal, signed to agree with it.")};
    c.guides = {1, -1, {},
                "The hand joint first, then finger joints named FINGER.N (thumb.0, thumb.1, index.0, ...), "
                "fingers listed across the hand."};
    c.controls = {{"hand", "square", "yellow", 0.15,
                   "The hand control; drives the hand joint unless the parent (a limb) already does."},
                  {"finger", "circle", "lightBlue", 0.04, "One FK control per finger joint."}};
    c.hooks = {"hand"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "twist";
    c.help = "Twist joints between a start and an end joint, sharing the end's twist along the bone.";
    c.params = {p_int("count", 3, 1, 16, "Number of twist joints."),
                p_enum("axis", "y", {"x", "y", "z"}, "The bone's axis (glTF from Blender: y).")};
    c.guides = {2, 2, {"start", "end"}, "The joints the twist runs between."};
    c.hooks = {"start", "end"};
    c.fixed_guides = -1;  // no controls
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "eye";
    c.help = "Eyes aimed at controls in front of them, with one master aim control.";
    c.params = {p_double("aimDistance", 0.5, 0.0, {}, "Distance of the aim controls in front of the eyes, m."),
                p_enum("aimAxis", "y", {"x", "y", "z", "-x", "-y", "-z"}, "The eye joint's looking axis.")};
    c.guides = {1, -1, {}, "The eye joints."};
    c.controls = {{"aim", "circle", "yellow", 0.05, "One aim control per eye."},
                  {"master", "square", "yellow", 0.15, "Moves every aim control."}};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "tail";
    c.help = "A tail or tentacle: the joints follow a spline moved by a few controls.";
    c.params = {p_int("controlCount", 3, 2, 32, "Number of spline controls."),
                p_bool("stretch", true, "The joints stretch with the spline.")};
    c.guides = {3, -1, {}, "The joints, root first."};
    c.controls = {{"main", "circle", "green", 0.2, "The spline controls."}};
    c.hooks = {"guide[i]"};
    c.features = {"stretch"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "simple";
    c.help =
        "Wraps given nodes: an existing control is adopted as it is; for any other node a control is made "
        "at the guide and drives it.";
    c.params = {p_enum("constrain", "parent", {"parent", "point", "orient", "none"},
                       "How a made control drives its node.")};
    c.guides = {1, -1, {}, "The nodes to wrap (guide joint = node name)."};
    c.controls = {{"main", "circle", "yellow", 0.2, "Controls made for nodes that are not controls."}};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "control";
    c.help = "A plain control (mGear's control_01): one control at its guide, driving the guide's joint when it names "
             "one; children hang from it.";
    c.guides = {1, 1, {"main"}, "Where the control sits: a joint it drives, or values."};
    c.controls = {{"main", "circle", "yellow", 0.3, "The control."}};
    c.hooks = {"main"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "meta";
    c.help = "A grouping component with no controls: a group at each guide, following the attach point, published "
             "as the hooks children hang from (mGear's meta_01 locators).";
    c.guides = {1, -1, {}, "Where the groups sit: joints (their places only; nothing is driven) or values."};
    c.hooks = {"guide[i]"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "mouth";
    c.help = "Jaw and lips: a jaw control turning the jaw joint; upper and lower lip controls that follow the jaw by "
             "fractions, and lip corners halfway between.";
    c.params = {p_double("upperLipFollow", 0.1, 0.0, 1.0, "How much of the jaw's motion the upper lip takes."),
                p_double("lowerLipFollow", 1.0, 0.0, 1.0, "How much of the jaw's motion the lower lip takes."),
                p_double("cornerFollow", 0.5, 0.0, 1.0, "How much of the jaw's motion the lip corners take.")};
    c.guides = {3, 5, {},
                "The jaw joint (its pivot), the upper and lower lip joints, and optionally the two lip corners: "
                "joints, in that order."};
    c.controls = {{"jaw", "square", "yellow", 0.1, "Turns the jaw joint about its pivot."},
                  {"lip", "circle", "lightBlue", 0.02,
                   "One per lip joint (upper, lower, corners), each under a group following the jaw by its "
                   "fraction."}};
    c.hooks = {"jaw", "upperLip", "lowerLip"};
    c.fixed_guides = 1;  // the jaw control turns the jaw joint about its own pivot
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "brows";
    c.help = "Brows: a control per brow joint, all following a main control by a falloff from the inner brow "
             "to the outer.";
    c.params = {p_double("innerFollow", 1.0, 0.0, 1.0, "How much of the main control's motion the first (inner) brow takes."),
                p_double("outerFollow", 0.5, 0.0, 1.0,
                         "How much the last (outer) brow takes; those between, linearly between the two.")};
    c.guides = {1, -1, {}, "The brow joints, inner first."};
    c.controls = {{"main", "square", "yellow", 0.06, "Moves every brow by its share."},
                  {"brow", "circle", "lightBlue", 0.015, "One per brow joint, under its follow group."}};
    c.hooks = {"main"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "eyelid";
    c.help = "Eyelids: upper and lower lid controls that follow the eye's turn by fractions and close in a "
             "blink (keyable on the eyelid node).";
    c.params = {p_double("upperFollow", 0.4, 0.0, 1.0, "How much of the eye's turn (about axis) the upper lid takes."),
                p_double("lowerFollow", 0.2, 0.0, 1.0, "How much of it the lower lid takes."),
                p_double("gap", 30.0, 0.0, 180.0, "The angle between the open lids, degrees: what a blink closes."),
                p_double("blinkHeight", 0.3, 0.0, 1.0, "Where the lids meet: 0 at the lower lid, 1 at the upper."),
                p_enum("axis", "x", {"x", "y", "z", "-x", "-y", "-z"},
                       "The lids' hinge in the eye's parent's frame; turning about it closes the upper lid (x for a "
                       "face looking along +z, as glTF's).")};
    c.guides = {3, 3, {"eye", "upper", "lower"}, "The eye joint, the upper and the lower lid joints."};
    c.controls = {{"lid", "circle", "lightBlue", 0.03, "One per lid, under a group that follows the eye and blinks."}};
    c.hooks = {"upper", "lower"};
    c.fixed_guides = 1;  // the eye guide only reads the eye
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "blendShapeSliders";
    c.help = "Slider controls driving a blendShape node's target weights (a face's or a corrective's shapes).";
    c.params = {p_string("blendShape", "", "The blendShape node's name; empty: the scene's only one."),
                p_string("targets", "", "The targets, by name or index, comma-separated; empty: every target."),
                p_double("spacing", 0.05, 0.0, {}, "The distance between the sliders, m."),
                p_double("min", 0.0, {}, {}, "The lowest weight a slider gives."),
                p_double("max", 1.0, {}, {}, "The highest weight a slider gives.")};
    c.guides = {1, 1, {"panel"}, "Where the slider column stands: a joint or values."};
    c.controls = {{"slider", "square", "yellow", 0.02,
                   "One per target, in a column below the panel; translateY adds to the weight."}};
    c.hooks = {"panel"};
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "corrective";
    c.help = "A pose reader: how far a driver joint's axis swings takes a corrective joint to an offset and/or a "
             "blend shape target's weight from 0 to 1.";
    c.params = {p_enum("axis", "y", {"x", "y", "z"}, "The driver's axis whose swing is read (glTF from Blender: y)."),
                p_double("startAngle", 0.0, 0.0, 180.0, "The swing (degrees) where the correction starts."),
                p_double("endAngle", 90.0, 0.0, 180.0, "The swing (degrees) where it is whole."),
                p_vec3("offset", math::Vec3(math::Vec3::Zero()), "The corrective joint's translate at the whole correction, added "
                                                     "to its rest."),
                p_string("blendShape", "", "The blendShape node of the target; empty: the scene's only one."),
                p_string("target", "", "A blend shape target (name or index) weighted 0 to 1; empty: none.")};
    c.guides = {1, 2, {}, "The driver joint, then the corrective joint (optional with a target)."};
    c.fixed_guides = -1;  // no controls: the driver's pose is the control
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "piston";
    c.help = "A piston: two joints that keep pointing at each other, each following a control.";
    c.guides = {2, 2, {"start", "end"}, "The two joints (the cylinder's and the rod's)."};
    c.controls = {{"start", "cube", "yellow", 0.08, "Moves the start joint; the start aims at the end control."},
                  {"end", "cube", "yellow", 0.08, "Moves the end joint; the end aims at the start control."}};
    c.hooks = {"start", "end"};
    c.fixed_guides = -1;  // the controls stand at the joints
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "squash";
    c.help = "Squash and stretch: a joint that aims at an end control and stretches to reach it, keeping its volume.";
    c.params = {p_enum("axis", "y", {"x", "y", "z"}, "The joint's axis it stretches along (glTF from Blender: y)."),
                p_double("volume", 1.0, 0.0, 1.0,
                         "How much the other two axes shrink as it stretches: 1 keeps the volume, 0 only stretches.")};
    c.guides = {2, 2, {"start", "end"}, "The joint that squashes, and its end (a joint or values)."};
    c.controls = {{"start", "circle", "yellow", 0.1, "Moves and turns the whole squash."},
                  {"end", "cube", "yellow", 0.06, "The end: the joint aims at it and stretches to reach it."}};
    c.hooks = {"start", "end"};
    c.fixed_guides = 1;  // the start control stands at the joint
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "wheel";
    c.help = "A wheel that rolls as it travels: its turn about the axle follows the distance moved forward.";
    c.params = {p_double("radius", 0.3, 0.0, {}, "The wheel's radius, m."),
                p_enum("axle", "x", {"x", "y", "z", "-x", "-y", "-z"}, "The joint's axis the wheel turns about."),
                p_enum("forward", "z", {"x", "y", "z", "-x", "-y", "-z"},
                       "The joint's axis the wheel rolls along (axle = up x forward rolls it the right way).")};
    c.guides = {1, 1, {"wheel"}, "The wheel's joint."};
    c.controls = {{"main", "circle", "yellow", 0.4, "Moves the wheel; it rolls by the distance moved forward."},
                  {"spin", "circle", "orange", 0.3, "A manual turn on top of the roll."}};
    c.hooks = {"hub", "wheel"};
    c.fixed_guides = -1;  // the controls stand at the joint
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "ephemeral";
    c.help = "Ephemeral rigging (seeds 000, 001): one control per joint below the guide joint, with relations.";
    c.params = {p_enum("keyScope", "character", {"character", "controls"},
                       "character: keying one control keys the whole pose."),
                p_bool("keepAnimation", true, "Move the joints' animation onto the controls.")};
    c.guides = {0, 1, {}, "The root joint of the hierarchy to rig (none: the whole character)."};
    c.controls = {{"joint", "sphere", "yellow", 0.05, "One control per joint."}};
    c.hooks = {"guide[i]"};
    c.fixed_guides = -1;  // the controls hold the joints' pose
    s.push_back(std::move(c));
  }
  {
    ComponentSchema c;
    c.type = "call";
    c.help =
        "Runs a registered build function (a build graph's function node; docs/BUILD_GRAPH.md) as one build step, "
        "after the components it reads.";
    c.params = {p_string("function", "", "The build function's id."),
                p_string("args", "{}",
                         "Its inputs, a JSON object: values, {\"$component\": RIGID} or {\"$output\": [RIGID, NAME]}.")};
    c.guides = {0, 0, {}, "None."};
    c.check = check_call;
    s.push_back(std::move(c));
  }
  return s;
}

}  // namespace

SchemaRegistry& extensible_schemas() {
  static SchemaRegistry registry = [] {
    SchemaRegistry r;
    for (ComponentSchema& s : make_schemas()) {
      Status st = r.add(std::move(s));
      if (!st) {
        std::fprintf(stderr, "rigel: built-in component schema: %s\n", st.message().c_str());
        std::abort();
      }
    }
    return r;
  }();
  return registry;
}

const SchemaRegistry& builtin_schemas() { return extensible_schemas(); }

}  // namespace rigel::rig
