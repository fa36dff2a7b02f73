// The whole generator as one call: load -> repair -> orient and place -> sample overhangs ->
// grow the tree -> size struts -> bodies, plus the columns baseline for the same samples.
// Nothing is written here; output/ writes what this computes.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "mesh/repair.hpp"
#include "orient/orient.hpp"
#include "overhang/overhang.hpp"
#include "struts/struts.hpp"

namespace cs {

class ModelQuery;

struct Job {
    std::string input;           // mesh file
    double scale = 1;            // applied first
    std::optional<double> fit;   // then scale so the largest side is this (mm)
    std::string orient = "auto"; // auto | keep | RX,RY,RZ
    bool self_intersection_check = true;
    bool timings = true;          // stage times in the report (the only part that differs run to run)
    Params params;
};

// What one strategy built for the placed model.
struct Supports {
    SizedTree sized;
    std::vector<Body> bodies;
    Mesh mesh;
    double volume = 0;  // sum of the bodies' volumes (mm^3)
    double length = 0;  // total strut length (mm)
};

struct Stage {
    std::string name;
    double seconds;
};

struct Result {
    std::string name;          // input file name without folder and extension
    std::string input_sha256;
    Mesh model;                // placed on the bed
    RepairReport repair;
    std::size_t self_intersections = 0;  // pairs, counted up to a limit
    Placement placement;
    Orientation orientation;
    OverhangSamples samples;
    Supports supports;         // by params.strategy
    Supports columns;          // the baseline, same samples
    std::vector<Stage> stages;
    std::vector<std::string> warnings;
};

// Throws InputError for unusable input and ParameterError for bad parameters.
// `progress` (may be empty) is told each stage's name as it starts.
Result run_job(const Job& job, const std::function<void(const std::string&)>& progress = {});

// Builds supports for an already placed model (used by run_job and orientation scoring).
Supports build_supports(const Mesh& placed, const std::vector<Sample>& samples, const Params& p);
// The same, with an index of the placed model already built.
Supports build_supports(const ModelQuery& placed, const std::vector<Sample>& samples, const Params& p);

std::string sha256_hex(std::string_view bytes);
std::string file_sha256(const std::string& path);

}  // namespace cs
