#include "holo/sim/visitor_plan.hpp"

#include "holo/core/error.hpp"

namespace holo::sim {

std::vector<std::string> visitorModelNames() {
  return {"figures", "bodies"};
}

VisitorModel visitorModelFromName(const std::string& name, const std::string& origin,
                                  const std::string& field) {
  if (name == "figures") return VisitorModel::figures;
  if (name == "bodies") return VisitorModel::bodies;
  throw InputError(origin, field, "a visitor model: figures or bodies", name);
}

}  // namespace holo::sim
