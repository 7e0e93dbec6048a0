// SRDF reading with tinyxml2: <disable_collisions>, <group> and <group_state>.
#include "fcl_rs/robot/srdf.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <stdexcept>

#include <tinyxml2.h>

namespace fcl_rs {
namespace {

/// Parses the SRDF into doc and returns its <robot> root; throws std::runtime_error naming the file otherwise.
const tinyxml2::XMLElement* openSrdf(const std::string& srdf_path, tinyxml2::XMLDocument& doc)
{
  const tinyxml2::XMLError err = doc.LoadFile(srdf_path.c_str());
  if (err == tinyxml2::XML_ERROR_FILE_NOT_FOUND || err == tinyxml2::XML_ERROR_FILE_COULD_NOT_BE_OPENED ||
      err == tinyxml2::XML_ERROR_FILE_READ_ERROR)
    throw std::runtime_error("fcl_rs: cannot open SRDF file '" + srdf_path + "'");
  if (err != tinyxml2::XML_SUCCESS)
    throw std::runtime_error("fcl_rs: SRDF '" + srdf_path + "' line " + std::to_string(doc.ErrorLineNum()) +
                             ": malformed XML (" + doc.ErrorStr() + ")");
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "robot")
    throw std::runtime_error("fcl_rs: SRDF '" + srdf_path + "': the root element is not <robot>");
  return root;
}

[[noreturn]] void failAt(const std::string& srdf_path, const tinyxml2::XMLElement& e, const std::string& what)
{
  throw std::runtime_error("fcl_rs: SRDF '" + srdf_path + "' line " + std::to_string(e.GetLineNum()) + ": " + what);
}

/// The element's attribute; fails naming the element when it is missing.
std::string required(const std::string& srdf_path, const tinyxml2::XMLElement& e, const char* attribute)
{
  const char* value = e.Attribute(attribute);
  if (!value) failAt(srdf_path, e, std::string("<") + e.Name() + "> has no " + attribute + " attribute");
  return value;
}

/// Resolves <group> elements to the robot's joints they hold, each group once (groups may include groups
/// defined after them).
class GroupResolver
{
public:
  GroupResolver(const std::string& srdf_path, const RobotModel& robot, const tinyxml2::XMLElement& root)
    : path_(srdf_path), robot_(robot)
  {
    for (std::size_t j = 0; j < robot.joints.size(); ++j) joint_index_[robot.joints[j].name] = int(j);
    for (const tinyxml2::XMLElement* v = root.FirstChildElement("virtual_joint"); v;
         v = v->NextSiblingElement("virtual_joint"))
      virtual_joints_.insert(required(path_, *v, "name"));
    passive_.assign(robot.joints.size(), false);
    for (const tinyxml2::XMLElement* p = root.FirstChildElement("passive_joint"); p;
         p = p->NextSiblingElement("passive_joint"))
      passive_[std::size_t(jointNamed(*p, required(path_, *p, "name")))] = true;
    for (const tinyxml2::XMLElement* g = root.FirstChildElement("group"); g; g = g->NextSiblingElement("group"))
    {
      const std::string name = required(path_, *g, "name");
      if (!elements_.emplace(name, g).second) failAt(path_, *g, "group '" + name + "' is defined twice");
      order_.push_back(name);
    }
  }

  const std::vector<std::string>& names() const { return order_; }
  const tinyxml2::XMLElement& element(const std::string& name) const { return *elements_.at(name); }
  bool has(const std::string& name) const { return elements_.count(name) > 0; }

  /// Whether each robot joint is in the group.
  const std::vector<bool>& joints(const std::string& name)
  {
    if (const auto done = resolved_.find(name); done != resolved_.end()) return done->second;
    const tinyxml2::XMLElement& g = *elements_.at(name);
    if (std::find(visiting_.begin(), visiting_.end(), name) != visiting_.end())
      failAt(path_, g, "group '" + name + "' includes itself");
    visiting_.push_back(name);
    std::vector<bool> in(robot_.joints.size(), false);
    for (const tinyxml2::XMLElement* e = g.FirstChildElement(); e; e = e->NextSiblingElement())
    {
      const std::string kind = e->Name();
      if (kind == "joint")
      {
        const std::string joint = required(path_, *e, "name");
        if (!isVirtual(joint)) in[std::size_t(jointNamed(*e, joint))] = true;
      }
      else if (kind == "link")
      {
        const int joint = robot_.links[std::size_t(linkNamed(*e, required(path_, *e, "name")))].parent_joint;
        if (joint >= 0) in[std::size_t(joint)] = true;
      }
      else if (kind == "chain")
        addChain(*e, in);
      else if (kind == "group")
      {
        const std::string sub = required(path_, *e, "name");
        if (!has(sub)) failAt(path_, *e, "group '" + name + "' includes group '" + sub + "', which is not defined");
        const std::vector<bool>& more = joints(sub);
        for (std::size_t j = 0; j < in.size(); ++j) in[j] = in[j] || more[j];
      }
      else
        failAt(path_, *e, "<group> holds <" + kind + ">, which is not <joint>, <link>, <chain> or <group>");
    }
    visiting_.pop_back();
    return resolved_.emplace(name, std::move(in)).first->second;
  }

  /// A <virtual_joint>: the robot's root in the planner's world, which fcl_rs does not move (no variable).
  bool isVirtual(const std::string& joint) const { return virtual_joints_.count(joint) > 0; }
  /// A <passive_joint>: a joint no planner moves (its variable stays out of every group).
  bool isPassive(int joint) const { return passive_[std::size_t(joint)]; }

  int jointNamed(const tinyxml2::XMLElement& e, const std::string& joint) const
  {
    const auto it = joint_index_.find(joint);
    if (it == joint_index_.end())
      failAt(path_, e, "joint '" + joint + "' is not a joint of robot '" + robot_.name + "'");
    return it->second;
  }

private:
  int linkNamed(const tinyxml2::XMLElement& e, const std::string& link) const
  {
    const int index = robot_.linkIndex(link);
    if (index < 0) failAt(path_, e, "link '" + link + "' is not a link of robot '" + robot_.name + "'");
    return index;
  }

  /// The joints from the tip link up to the base link.
  void addChain(const tinyxml2::XMLElement& e, std::vector<bool>& in) const
  {
    const std::string base = required(path_, e, "base_link"), tip = required(path_, e, "tip_link");
    const int base_link = linkNamed(e, base);
    std::vector<int> chain;
    for (int link = linkNamed(e, tip); link != base_link;)
    {
      const int joint = robot_.links[std::size_t(link)].parent_joint;
      if (joint < 0) failAt(path_, e, "chain base link '" + base + "' is not an ancestor of tip link '" + tip + "'");
      chain.push_back(joint);
      link = robot_.joints[std::size_t(joint)].parent_link;
    }
    for (int joint : chain) in[std::size_t(joint)] = true;
  }

  std::string path_;
  const RobotModel& robot_;
  std::map<std::string, int> joint_index_;
  std::set<std::string> virtual_joints_;
  std::vector<bool> passive_;
  std::map<std::string, const tinyxml2::XMLElement*> elements_;
  std::vector<std::string> order_;
  std::map<std::string, std::vector<bool>> resolved_;
  std::vector<std::string> visiting_;
};

/// The text as one finite number, or nothing.
bool parseNumber(const char* text, double& value)
{
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text, &end);
  if (end == text || errno == ERANGE || !std::isfinite(value)) return false;
  while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r') ++end;
  return *end == '\0';
}

}  // namespace

std::vector<DisabledCollision> loadDisabledCollisions(const std::string& srdf_path, const RobotModel& robot)
{
  tinyxml2::XMLDocument doc;
  const tinyxml2::XMLElement* root = openSrdf(srdf_path, doc);
  std::vector<DisabledCollision> pairs;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement("disable_collisions"); e;
       e = e->NextSiblingElement("disable_collisions"))
  {
    DisabledCollision d;
    d.source = srdf_path + ":" + std::to_string(e->GetLineNum());
    for (const char* attribute : {"link1", "link2"})
    {
      const std::string value = required(srdf_path, *e, attribute);
      if (robot.linkIndex(value) < 0)
        failAt(srdf_path, *e,
               std::string("<disable_collisions ") + attribute + "=\"" + value + "\"> names no link of robot '" +
                   robot.name + "'");
      (std::string(attribute) == "link1" ? d.link1 : d.link2) = value;
    }
    if (const char* reason = e->Attribute("reason")) d.reason = reason;
    pairs.push_back(std::move(d));
  }
  return pairs;
}

PlanningGroups loadPlanningGroups(const std::string& srdf_path, const RobotModel& robot)
{
  tinyxml2::XMLDocument doc;
  const tinyxml2::XMLElement* root = openSrdf(srdf_path, doc);
  GroupResolver resolver(srdf_path, robot, *root);
  PlanningGroups out;
  for (const std::string& name : resolver.names())
  {
    PlanningGroup group;
    group.name = name;
    group.dof = robot.numVariables();
    group.source = srdf_path + ":" + std::to_string(resolver.element(name).GetLineNum());
    const std::vector<bool>& in = resolver.joints(name);
    for (int j : robot.variable_joints)
      if (in[std::size_t(j)] && !resolver.isPassive(j))
        group.variables.push_back(robot.joints[std::size_t(j)].variable);
    out.groups.push_back(std::move(group));
  }
  for (const tinyxml2::XMLElement* e = root->FirstChildElement("group_state"); e;
       e = e->NextSiblingElement("group_state"))
  {
    GroupState state;
    state.name = required(srdf_path, *e, "name");
    state.group = required(srdf_path, *e, "group");
    state.source = srdf_path + ":" + std::to_string(e->GetLineNum());
    if (!resolver.has(state.group))
      failAt(srdf_path, *e, "group state '" + state.name + "' is of group '" + state.group + "', which is not defined");
    for (const GroupState& earlier : out.states)
      if (earlier.name == state.name && earlier.group == state.group)
        failAt(srdf_path, *e, "group state '" + state.name + "' of group '" + state.group + "' is defined twice");
    const std::vector<bool>& in = resolver.joints(state.group);
    for (const tinyxml2::XMLElement* j = e->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    {
      const std::string joint_name = required(srdf_path, *j, "name");
      if (resolver.isVirtual(joint_name)) continue;
      const int index = resolver.jointNamed(*j, joint_name);
      const RobotJoint& joint = robot.joints[std::size_t(index)];
      if (!in[std::size_t(index)])
        failAt(srdf_path, *j, "group state '" + state.name + "' sets joint '" + joint_name + "', which group '" +
                                  state.group + "' does not hold");
      if (joint.type == JointType::kFixed)
        failAt(srdf_path, *j, "group state '" + state.name + "' sets the fixed joint '" + joint_name + "'");
      const std::string text = required(srdf_path, *j, "value");
      double value = 0;
      if (!parseNumber(text.c_str(), value))
        failAt(srdf_path, *j, "joint '" + joint_name + "' has value \"" + text + "\", which is not one finite number");
      if (joint.variable >= 0) state.values.emplace_back(joint.variable, value);
    }
    out.states.push_back(std::move(state));
  }
  return out;
}

const PlanningGroup& PlanningGroups::group(const std::string& name) const
{
  for (const PlanningGroup& g : groups)
    if (g.name == name) return g;
  std::string known;
  for (const PlanningGroup& g : groups) known += (known.empty() ? "'" : ", '") + g.name + "'";
  throw std::invalid_argument("fcl_rs: no planning group '" + name + "' (the SRDF defines " +
                              (known.empty() ? std::string("none") : known) + ")");
}

const GroupState& PlanningGroups::state(const std::string& name, const std::string& group) const
{
  const GroupState* found = nullptr;
  for (const GroupState& s : states)
    if (s.name == name && (group.empty() || s.group == group))
    {
      if (found)
        throw std::invalid_argument("fcl_rs: group state '" + name + "' is defined for groups '" + found->group +
                                    "' and '" + s.group + "'; name the group");
      found = &s;
    }
  if (!found)
    throw std::invalid_argument("fcl_rs: no group state '" + name + "'" +
                                (group.empty() ? "" : " of group '" + group + "'"));
  return *found;
}

}  // namespace fcl_rs
