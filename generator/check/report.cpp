// What `check` prints: a line per check, the places that failed, and the same as JSON.
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "check/check.hpp"

namespace cs {
namespace {

const char* mark(bool ok) { return ok ? "ok  " : "FAIL"; }


std::string mm(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", v);
    return b;
}

nlohmann::ordered_json xyz(const Vec3& p) { return {p.x, p.y, p.z}; }

}  // namespace

std::string format_place(const Vec3& p) {
    char b[96];
    std::snprintf(b, sizeof b, "(%.2f, %.2f, %.2f)", p.x, p.y, p.z);
    return b;
}

std::string CheckResult::summary() const {
    std::ostringstream s;
    s << mark(coverage_ok()) << " coverage     " << covered << " of " << (overhang_points - exempt - left_out - omitted)
      << " overhang points have a contact within " << mm(reach) << " mm (" << face_points << " on faces, "
      << ridge_points << " on ridges, " << lowest_points << " lowest points; " << exempt
      << " rest on what is below; " << contacts << " contacts)\n";
    s << "       largest gap to a contact " << mm(largest_gap) << " mm at " << format_place(largest_gap_at) << "; "
      << mm(uncovered_area) << " mm2 of overhang beyond reach\n";
    for (const auto& u : uncovered) s << "       uncovered at " << format_place(u) << "\n";
    if (blocked_regions)
        s << "     left out     " << left_out << " overhang points (" << mm(left_out_area) << " mm2) in "
          << blocked_regions << " blocked region" << (blocked_regions == 1 ? "" : "s") << ": left out on purpose\n";
    if (omitted_struts)
        s << "     left out     " << omitted << " overhang points (" << mm(omitted_area) << " mm2) that the "
          << omitted_tips << " tips of " << omitted_struts << " omitted strut" << (omitted_struts == 1 ? "" : "s")
          << (omitted_pieces ? " and the " + std::to_string(omitted_pieces) + " hybrid piece" + (omitted_pieces == 1 ? "" : "s") + " on them" : "")
          << " held (omit_struts): left out on purpose by the user's edit\n";
    s << mark(gap_ok()) << " air gap      " << fused_contacts << " contacts closer to the model than the gap";
    if (min_air_gap < INFINITY) s << " (smallest " << mm(min_air_gap) << " mm at " << format_place(min_air_gap_at) << ")";
    s << "\n";
    s << mark(penetrating_bodies == 0) << " penetration  " << penetrating_bodies
      << " solids reach into the model (deepest " << mm(max_penetration) << " mm outside contact ends)"
      << (model_closed ? "" : " [the model has holes: inside is a best guess]") << "\n";
    s << mark(ungrounded_bodies + buried_bottoms == 0) << " grounding    " << ungrounded_bodies << " of " << bodies
      << " solids rest on nothing, " << buried_bottoms << " start inside the model\n";
    s << mark(open_bodies + inward_bodies == 0) << " closed       " << open_bodies << " open, " << inward_bodies
      << " inward-facing solids\n";
    s << mark(steep_bodies == 0) << " angles       " << steep_bodies << " solids steeper than the critical angle (max "
      << mm(max_angle) << " deg)\n";
    s << mark(weak_bodies == 0) << " strength     " << weak_bodies
      << " solids longer for their width than the strength rule allows (worst length-to-width ratio "
      << mm(worst_length_to_width) << ")\n";
    for (const auto& f : flagged) s << "       " << f.what << "\n";
    return s.str();
}

std::string CheckResult::json() const {
    nlohmann::ordered_json j;
    j["ok"] = ok();
    nlohmann::ordered_json unc = nlohmann::ordered_json::array();
    for (const auto& u : uncovered) unc.push_back(xyz(u));
    j["coverage"] = {{"ok", coverage_ok()},           {"points", overhang_points}, {"covered", covered},
                     {"exempt", exempt},              {"face_points", face_points}, {"ridge_points", ridge_points},
                     {"lowest_points", lowest_points}, {"contacts", contacts},       {"reach_mm", reach},
                     {"largest_gap_mm", largest_gap}, {"largest_gap_at", xyz(largest_gap_at)},
                     {"uncovered_area_mm2", uncovered_area}, {"uncovered", unc},
                     {"left_out_on_purpose", {{"points", left_out}, {"area_mm2", left_out_area}, {"regions", blocked_regions},
                                              {"omitted_struts", {{"struts", omitted_struts}, {"tips", omitted_tips}, {"pieces", omitted_pieces},
                                                                  {"points", omitted}, {"area_mm2", omitted_area}}}}}};
    j["air_gap"] = {{"ok", gap_ok()}, {"fused", fused_contacts},
                    {"min_mm", min_air_gap < INFINITY ? nlohmann::ordered_json(min_air_gap) : nlohmann::ordered_json()}};
    j["penetration"] = {{"bodies", penetrating_bodies}, {"max_mm", max_penetration}, {"model_closed", model_closed}};
    j["grounding"] = {{"ungrounded", ungrounded_bodies}, {"buried_bottoms", buried_bottoms}};
    j["closed"] = {{"open", open_bodies}, {"inward", inward_bodies}};
    j["angles"] = {{"steep", steep_bodies}, {"max_deg", max_angle}};
    j["bodies"] = bodies;
    j["strength"] = {{"weak", weak_bodies}, {"worst_length_to_width", worst_length_to_width}};
    j["worst_length_to_width"] = worst_length_to_width;
    nlohmann::ordered_json fl = nlohmann::ordered_json::array();
    for (const auto& f : flagged) fl.push_back({{"what", f.what}, {"at", xyz(f.at)}});
    j["failures"] = fl;
    return j.dump(2);
}

}  // namespace cs
