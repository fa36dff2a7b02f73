#include "core/params.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"

namespace cs {

std::string Params::validate() const {
    auto bad = [](const char* name, double v, const char* range) {
        return std::string(name) + " = " + std::to_string(v) + " is out of range (" + range + ")";
    };
    if (!(critical_angle >= 5 && critical_angle <= 80)) return bad("critical_angle", critical_angle, "5..80 degrees");
    if (!(layer_height > 0.01 && layer_height <= 2)) return bad("layer_height", layer_height, "0.01..2 mm");
    if (!(wall_thickness > 0.05 && wall_thickness <= 5)) return bad("wall_thickness", wall_thickness, "0.05..5 mm");
    if (!(sampling_distance >= 0.05 && sampling_distance <= 50))
        return bad("sampling_distance", sampling_distance, "0.05..50 mm");
    if (!(tip_length >= 0 && tip_length <= 20)) return bad("tip_length", tip_length, "0..20 mm");
    if (!(tip_diameter > 0 && tip_diameter <= 10)) return bad("tip_diameter", tip_diameter, "0..10 mm");
    if (!(gap >= 0 && gap <= 5)) return bad("gap", gap, "0..5 mm");
    if (!(k >= 0 && k <= 1)) return bad("k", k, "0..1 mm per (mm*degree)");
    if (!(d_min > 0 && d_min <= 50)) return bad("d_min", d_min, "0..50 mm");
    if (!(d_max >= d_min && d_max <= 100)) return bad("d_max", d_max, "d_min..100 mm");
    if (!(strength_length > 0)) return bad("strength_length", strength_length, "> 0 mm");
    if (!(foot_height >= 0 && foot_height <= 20)) return bad("foot_height", foot_height, "0..20 mm");
    if (!(foot_extra >= 0 && foot_extra <= 20)) return bad("foot_extra", foot_extra, "0..20 mm");
    if (!(model_clearance >= 0 && model_clearance <= 10)) return bad("model_clearance", model_clearance, "0..10 mm");
    return "";
}

const std::vector<Preset>& presets() {
    static const std::vector<Preset> all = [] {
        std::vector<Preset> v;
        Params g;  // defaults above are the generic preset
        v.push_back({"generic-0.4",
                     "Any current FDM printer, 0.4 mm nozzle, PLA: 50 deg overhangs, 0.2 mm layers, 0.5 mm N walls "
                     "(0.4 mm walls vanish in slicers), 2.5 mm sampling (a tip every 2.5 mm, as dense as slicers' 15% line "
                     "supports), "
                     "0.8 mm tips",
                     g,
                     "angle: the benchmark slicer profile (Cura/Prusa support angle 50); walls: slicer notes pitfall 6 "
                     "(0.4 mm walls kept 9-16% in CuraEngine, 0.5 mm kept all); tips: 0.5 mm rods vanish when sliced, "
                     "0.8 mm is Cura's tree-support tip; sampling: measured (bench: 2.5 mm used 44-49% less support "
                     "filament than 1.5 mm in CuraEngine, at full coverage); k, tip length: the paper"});

        Params r = g;
        r.preset = "replicator2-pla";
        r.critical_angle = 50;   // paper Sec. 7: measured on the Replicator 2
        r.layer_height = 0.2;    // paper: standard layer thickness
        r.line_width = 0.4;
        r.k = 0.0015;            // paper Eqn (1)
        r.tip_length = 1.0;      // paper Sec. 6
        r.tip_diameter = 0.6;
        r.sampling_distance = 0.25;  // paper Sec. 4
        r.d_min = 0.5;           // paper's tested diameters 0.5 .. 1.5
        r.d_max = 4.0;
        v.push_back({"replicator2-pla", "The paper's printer: MakerBot Replicator 2, PLA (Vanek et al. 2014)", r,
                     "critical angle, layers, k, 1 mm tips, 0.25 mm sampling: the paper (Sec. 4, 6, 7); d_min 0.5: the "
                     "paper's thinnest tested strut; walls 0.5 instead of 0.4 so slicers print them"});

        Params mk4 = g;
        mk4.preset = "prusa-mk4-pla";
        mk4.critical_angle = 55;  // PrusaSlicer's PLA profiles print 55 deg overhangs without support
        mk4.layer_height = 0.2;
        mk4.line_width = 0.45;    // PrusaSlicer MK4 0.4 nozzle default extrusion width
        mk4.wall_thickness = 0.5;
        mk4.sampling_distance = 3.0;
        v.push_back({"prusa-mk4-pla", "Prusa MK3S/MK4, 0.4 mm nozzle, PLA (good part cooling: 55 deg overhangs)", mk4,
                     "angle: PrusaSlicer's PLA profiles support from 55 deg; line width: its 0.45 mm default; sampling "
                     "3 mm: PLA with strong cooling bridges the 2.2 mm between tips cleanly"});

        Params petg = mk4;
        petg.preset = "prusa-mk4-petg";
        petg.critical_angle = 45;  // PETG sags more and runs with less fan
        petg.gap = 0.25;           // PETG sticks to itself: PrusaSlicer's PETG profiles widen the z gap
        petg.sampling_distance = 2.0;
        v.push_back({"prusa-mk4-petg", "Prusa MK3S/MK4, 0.4 mm nozzle, PETG (less cooling, stickier)", petg,
                     "angle 45: PETG runs with less fan and sags sooner; gap 0.25: PrusaSlicer's PETG profiles widen "
                     "the support z gap because PETG fuses to itself"});

        Params ender = g;
        ender.preset = "ender3-pla";
        ender.critical_angle = 45;  // stock single-sided fan duct: weaker overhangs
        ender.sampling_distance = 2.0;
        v.push_back({"ender3-pla", "Creality Ender-3 (stock cooling), 0.4 mm nozzle, PLA", ender,
                     "angle 45: the stock single-sided fan duct cools overhangs unevenly; the rest as generic-0.4"});
        return v;
    }();
    return all;
}

Params preset_params(const std::string& name) {
    std::string known;
    for (const auto& p : presets()) {
        if (p.name == name) return p.params;
        known += (known.empty() ? "" : ", ") + p.name;
    }
    throw ParameterError("unknown preset '" + name + "'; known presets: " + known);
}

// The paper's Table 1: 1 mm struts are safe to 30 mm at <= 30 deg; 1.5 mm struts to 60 mm at
// <= 50 deg. A safe length growing with d^2 (stiffness of a thin column against the nozzle's push)
// matches both points: 30 * 1.5^2 * 0.85 = 57 mm at 50 deg. Steeper struts lose 15% per 20 deg.
static double angle_factor(double angle_deg) {
    double a = std::max(0.0, angle_deg - 30.0);
    return std::max(0.3, 1.0 - 0.15 * a / 20.0);
}

double safe_length(const Params& p, double d, double angle_deg) {
    return p.strength_length * d * d * angle_factor(angle_deg);
}

double strength_width(const Params& p, double length, double angle_deg) {
    return std::sqrt(std::max(0.0, length) / (p.strength_length * angle_factor(angle_deg)));
}

double eqn1_width(const Params& p, double length, double angle_deg) {
    return std::clamp(p.k * length * angle_deg, p.d_min, p.d_max);
}

double merged_width(const Params& p, const std::vector<double>& widths) {
    double cubes = 0, widest = 0;
    for (double w : widths) cubes += w * w * w, widest = std::max(widest, w);
    return std::clamp(std::max(std::cbrt(cubes), widest), p.d_min, p.d_max);
}

}  // namespace cs
