// SRDF <disable_collisions> reading with tinyxml2.
#include "fcl_rs/robot/srdf.h"

#include <stdexcept>

#include <tinyxml2.h>

namespace fcl_rs {

std::vector<DisabledCollision> loadDisabledCollisions(const std::string& srdf_path, const RobotModel& robot)
{
  tinyxml2::XMLDocument doc;
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

  std::vector<DisabledCollision> pairs;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement("disable_collisions"); e;
       e = e->NextSiblingElement("disable_collisions"))
  {
    DisabledCollision d;
    d.source = srdf_path + ":" + std::to_string(e->GetLineNum());
    for (const char* attribute : {"link1", "link2"})
    {
      const char* value = e->Attribute(attribute);
      if (!value)
        throw std::runtime_error("fcl_rs: SRDF '" + srdf_path + "' line " + std::to_string(e->GetLineNum()) +
                                 ": <disable_collisions> has no " + attribute + " attribute");
      if (robot.linkIndex(value) < 0)
        throw std::runtime_error("fcl_rs: SRDF '" + srdf_path + "' line " + std::to_string(e->GetLineNum()) +
                                 ": <disable_collisions " + attribute + "=\"" + value + "\"> names no link of robot '" +
                                 robot.name + "'");
      (std::string(attribute) == "link1" ? d.link1 : d.link2) = value;
    }
    if (const char* reason = e->Attribute("reason")) d.reason = reason;
    pairs.push_back(std::move(d));
  }
  return pairs;
}

}  // namespace fcl_rs
