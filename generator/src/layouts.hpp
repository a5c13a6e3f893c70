#pragma once
// The indoor maps hunav_generate draws (generator/README.md, "Maps"): outer walls around
//  - rooms: the area split again and again by walls with doors (0.9-1.3 m), some splits a corridor
//    (1-3 m wide) between two walls, some walls with a second door (another way round);
//  - warehouse: rows of shelves (0.5-1.2 m deep, aisles 1.2-3 m) broken by gaps of 0.8-2 m, cross
//    aisles at the ends or a row against a wall (dead-end aisles);
//  - hall: an open room with tables on a loose grid and partitions reaching in from the walls;
// then random clutter. Nothing drawn after the walls (tables, clutter) comes within
// kFurnitureGap of other obstacles, so it narrows no passage below that.
#include <string>

#include "grid.hpp"
#include "rng.hpp"

namespace hunav::generator {

enum class Layout { Rooms, Warehouse, Hall };
const char* layoutName(Layout layout);

constexpr double kWallThickness = 0.15;  // m, inner walls (the outer ones are 0.2 m)
constexpr double kFurnitureGap = 0.9;    // m, least free space around furniture and clutter

// A free grid of width x height metres (its lower left corner at (-width/2, -height/2)) drawn with
// `layout`.
Grid drawMap(Layout layout, double width, double height, double resolution, Rng& rng);

}  // namespace hunav::generator
