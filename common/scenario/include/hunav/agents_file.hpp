#pragma once
#include "hunav/scenario.hpp"
#include "hunav/yaml_reader.hpp"

namespace hunav {
// Parses the people under `doc`: HuNavSim's agents layout (`hunav_loader:`, v1 and v1.5) and/or our
// seeded people generator (`generate:`, one mapping or a list; scenarios/README.md). `seed` drives the
// random behavior configurations (with each agent's id) and the generator. Generated people start at
// least `min_spacing` away from every agent placed before them and from `static_shapes`.
// `global_goals` (optional) receives HuNavSim 2's global_goals with integer ids.
std::vector<AgentConfig> parseAgents(const YamlReader& yr, const YAML::Node& doc, const std::string& where,
                                     std::uint64_t seed, const std::vector<Shape>& static_shapes = {},
                                     std::map<int, Vec2>* global_goals = nullptr);
}  // namespace hunav
