#pragma once
#include "hunav/scenario.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav {
// Parses the HuNavSim agents layout found under `doc` (which holds `hunav_loader:`).
std::vector<AgentConfig> parseAgents(const YamlReader& yr, const YAML::Node& doc, const std::string& where,
                                     std::uint64_t seed);
}  // namespace hunav
