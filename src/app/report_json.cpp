#include "cutdyn/app/report_json.hpp"

#include <cmath>
#include <variant>

#include "cutdyn/core/units.hpp"

namespace cutdyn::app {
namespace {

using json = nlohmann::json;
using units::m_to_mm;
using units::m_to_um;

const std::vector<CriticalDepth>* reference_of(const LobesJobReport& r) {
  return r.reference.empty() ? nullptr : &r.reference;
}

// The filter of an axis' estimate for its first step (docs/models/monitor.md §4.1).
json filter_json(const FilterReport& f) {
  json j{{"transfer_function", EstimateFilter::formula()},
         {"bandwidth_hz", f.bandwidth_hz},
         {"step_s", f.step_s}};
  if (f.step_s > 0.0) {
    j["minus_3db_hz"] = f.minus_3db_hz;
    j["delay_s"] = f.delay_s;
    if (f.tooth_frequency_hz > 0.0) {
      j["tooth_frequency_hz"] = f.tooth_frequency_hz;
      j["gain_at_tooth_frequency"] = f.gain_at_tooth_frequency;
      j["lag_deg_at_tooth_frequency"] = f.lag_deg_at_tooth_frequency;
    }
  }
  return j;
}

// Modes fitted to a measured FRF: [{direction, natural_hz, damping_ratio, stiffness_n_per_m,
// residue_phase_deg}].
json modes_json(const ModalModel& m) {
  json modes = json::array();
  for (const Mode& mode : m.modes)
    modes.push_back({{"direction", to_string(mode.direction)},
                     {"natural_hz", units::rad_per_s_to_hz(mode.natural_rad_s)},
                     {"damping_ratio", mode.damping_ratio},
                     {"stiffness_n_per_m", mode.stiffness_n_per_m},
                     {"residue_phase_deg", units::rad_to_deg(mode.residue_phase_rad)}});
  return modes;
}

}  // namespace

// One row of named values per speed, shared by the CSV and the JSON.
ReportTable lobes_table(const LobesJobReport& r) {
  ReportTable out;
  out.columns = {"spindle_rpm", "critical_depth_mm", "chatter_hz",
                 "lobe",        "bifurcation",       "beyond_limit"};
  if (r.duty_cycle) out.columns.push_back("duty_cycle");
  const auto* ref = reference_of(r);
  if (ref)
    out.columns.insert(out.columns.end(), {"conventional_depth_mm", "conventional_chatter_hz"});
  for (std::size_t i = 0; i < r.lobes.points.size(); ++i) {
    const LobePoint& p = r.lobes.points[i];
    std::vector<io::CsvCell> cells{p.rpm,
                                   m_to_mm(p.boundary.depth_m),
                                   p.boundary.chatter_hz,
                                   static_cast<long long>(p.lobe),
                                   std::string(to_string(p.boundary.bifurcation)),
                                   static_cast<long long>(p.boundary.found ? 0 : 1)};
    if (r.duty_cycle) cells.emplace_back(p.duty_cycle);
    if (ref) {
      cells.emplace_back(m_to_mm((*ref)[i].depth_m));
      cells.emplace_back((*ref)[i].chatter_hz);
    }
    out.rows.push_back(std::move(cells));
  }
  return out;
}

ReportTable trace_table(const MillingSimulationJobReport& job) {
  const MillingSimulationResult& r = job.result;
  ReportTable out;
  out.columns = {"time_s", "fx_n", "fy_n",         "force_n",
                 "x_um",   "y_um", "teeth_in_cut", "cutting_force_n"};
  for (std::size_t i = 0; i < r.time_s.size(); ++i)
    out.rows.push_back({r.time_s[i], r.fx_n[i], r.fy_n[i], r.force_n[i], m_to_um(r.x_m[i]),
                        m_to_um(r.y_m[i]), r.teeth_in_cut[i], r.cutting_force_n[i]});
  return out;
}

ReportTable sweep_table(const MillingSweepJobReport& job) {
  ReportTable out;
  const auto& names = milling_metric_names();
  out.columns = {job.sweep.key};
  out.columns.insert(out.columns.end(), names.begin(), names.end());
  out.columns.push_back("chatter");
  for (std::size_t i = 0; i < job.results.size(); ++i) {
    std::vector<io::CsvCell> row{job.sweep.values[i]};
    for (double m : milling_metrics(job.results[i])) row.emplace_back(m);
    row.emplace_back(job.results[i].chatter ? 1LL : 0LL);
    out.rows.push_back(std::move(row));
  }
  return out;
}

void write_csv(std::ostream& out, const ReportTable& table) {
  io::CsvWriter csv(out, table.columns);
  for (std::vector<io::CsvCell> row : table.rows) {
    for (io::CsvCell& cell : row)
      if (const double* v = std::get_if<double>(&cell); v && std::isnan(*v)) cell = std::string();
    csv.row(row);
  }
}

ReportTable trace_table(const DriveReport& run) {
  ReportTable out{{"axis", "time_s", "axis_force_n", "load_torque_nm", "speed_rad_s",
                   "position_error_um", "epsilon_um"},
                  {}};
  for (const DriveAxisReport& a : run.axes)
    for (std::size_t i = 0; i < a.drive.time_s.size(); ++i)
      if (a.drive.time_s[i] >= run.traces_from_s - 1e-12)
        out.rows.push_back({a.axis.name, a.drive.time_s[i], a.drive.axis_force_n[i],
                            a.drive.load_torque_nm[i], a.drive.speed_rad_s[i],
                            units::m_to_um(a.drive.position_error_m[i]),
                            units::m_to_um(a.epsilon_m[i])});
  return out;
}

ReportTable sweep_table(const DriveSweepReport& sweep) {
  const auto& names = drive_metric_names();
  ReportTable out{{sweep.key, "axis"}, {}};
  out.columns.insert(out.columns.end(), names.begin(), names.end());
  out.columns.emplace_back("chatter");
  for (std::size_t i = 0; i < sweep.runs.size(); ++i)
    for (const DriveAxisReport& a : sweep.runs[i].axes) {
      std::vector<io::CsvCell> row{sweep.values[i], a.axis.name};
      for (double m : drive_metrics(a)) row.emplace_back(m);  // NaN: none for this drive
      row.emplace_back(static_cast<long long>(sweep.runs[i].chatter ? 1 : 0));
      out.rows.push_back(std::move(row));
    }
  return out;
}

json to_json(const io::Case& c, const MillingSweepJobReport& job, const std::string& metric) {
  const auto& names = milling_metric_names();
  json points = json::array();
  for (std::size_t i = 0; i < job.results.size(); ++i) {
    const MillingSimulationResult& r = job.results[i];
    json p{{"value", job.sweep.values[i]}, {"chatter", r.chatter}, {"status", to_string(r.status)}};
    const auto m = milling_metrics(r);
    for (std::size_t k = 0; k < names.size(); ++k)
      p[names[k]] = std::isnan(m[k]) ? json() : json(m[k]);
    points.push_back(std::move(p));
  }
  return {{"command", "simulate"},      {"schema_version", kJsonSchemaVersion},
          {"case", io::to_json(c)},     {"source", c.source},
          {"sweep", job.sweep.key},     {"metric", metric},
          {"points", std::move(points)}};
}

ReportTable trace_table(const TurningSimulationJobReport& job) {
  ReportTable out;
  out.columns = {"process", "time_s", "displacement_um", "force_n", "chip_thickness_um"};
  for (const TurningSimulationRun& run : job.runs)
    for (std::size_t i = 0; i < run.result.time_s.size(); ++i)
      out.rows.push_back({run.name, run.result.time_s[i], m_to_um(run.result.displacement_m[i]),
                          run.result.force_n[i], m_to_um(run.result.chip_thickness_m[i])});
  return out;
}

json to_json(const io::Case& c, const LobesJobReport& r) {
  const ReportTable rows = lobes_table(r);
  const auto& pts = r.lobes.points;
  json points = json::array();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    json j = json::object();
    const auto& cells = rows.rows[i];
    for (std::size_t k = 0; k < rows.columns.size(); ++k)
      std::visit([&](const auto& v) { j[rows.columns[k]] = v; }, cells[k]);
    j["beyond_limit"] = !pts[i].boundary.found;
    points.push_back(std::move(j));
  }
  json doc = json_document("lobes", c);
  doc.update({{"method", r.method},
              {"seconds", r.lobes.seconds},
              {"evaluations", r.lobes.evaluations},
              {"lowest",
               {{"spindle_rpm", pts[r.lowest].rpm},
                {"critical_depth_mm", m_to_mm(pts[r.lowest].boundary.depth_m)}}},
              {"points", std::move(points)}});
  if (r.lobes.status != LobesStatus::kSuccess) doc["warning"] = r.lobes.message;
  if (!r.fitted_modes.modes.empty()) doc["fitted_modes"] = modes_json(r.fitted_modes);
  if (!r.warnings.empty()) doc["warnings"] = r.warnings;
  if (r.target_depth_m) {
    doc["target_depth_mm"] = m_to_mm(*r.target_depth_m);
    json ranges = json::array();
    for (const SpeedRange& s : r.stable_ranges)
      ranges.push_back({{"rpm_from", s.rpm_from}, {"rpm_to", s.rpm_to}});
    doc["stable_ranges"] = ranges;
    if (r.advice.found) {
      doc["recommended_rpm"] = r.advice.rpm;
      doc["recommended_margin"] = r.advice.margin;
      doc["recommended_range"] = {{"rpm_from", r.advice.range.rpm_from},
                                  {"rpm_to", r.advice.range.rpm_to}};
    }
  }
  return doc;
}

json to_json(const io::Case& c, const CheckJobReport& r) {
  const CriticalDepth& b = r.boundary;
  json doc{{"command", "check"},
           {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},
           {"source", c.source},
           {"method", r.method},
           {"spindle_rpm", r.rpm},
           {"depth_mm", m_to_mm(r.depth_m)},
           {"stable", r.stable},
           {"critical_depth_mm", m_to_mm(b.depth_m)},
           {"beyond_limit", !b.found},
           {"margin", nullptr},
           {"chatter_hz", b.chatter_hz},
           {"bifurcation", to_string(b.bifurcation)},
           {"lobe", r.lobe}};
  if (r.margin) doc["margin"] = *r.margin;
  if (b.truncated) doc["warning"] = "the method could not cover every mode at this speed";
  if (b.unconverged)
    doc["warning"] =
        "the critical depth still moved by more than the tolerance when the time step was halved";
  if (r.duty_cycle) doc["duty_cycle"] = *r.duty_cycle;
  if (r.conventional)
    doc["conventional"] = {{"critical_depth_mm", m_to_mm(r.conventional->boundary.depth_m)},
                           {"chatter_hz", r.conventional->boundary.chatter_hz},
                           {"stable", r.conventional->stable}};
  if (!r.fitted_modes.modes.empty()) doc["fitted_modes"] = modes_json(r.fitted_modes);
  if (!r.warnings.empty()) doc["warnings"] = r.warnings;
  return doc;
}

namespace {

json oxley_json(const io::Case& c, const OxleyPrediction& p) {
  const WorkMaterial& m = *c.material;
  const OxleyState& s = p.result.state;
  return {{"material", m.name},
          {"shear_angle_deg", units::rad_to_deg(s.phi_rad)},
          {"chip_thickness_mm", m_to_mm(s.chip_thickness_m)},
          {"chip_ratio", p.result.chip_ratio},
          {"strain_rate_constant", s.c0},
          {"secondary_zone_ratio", s.delta},
          {"contact_length_mm", m_to_mm(s.contact_length_m)},
          {"friction_angle_deg", units::rad_to_deg(s.friction_angle_rad)},
          {"shear_plane_temperature_c", s.temperature_ab_c},
          {"interface_temperature_c", s.temperature_interface_c},
          {"shear_plane_strain_rate_per_s", s.strain_rate_ab_per_s},
          {"shear_plane_flow_stress_mpa", s.shear_flow_stress_pa / 1e6},
          {"interface_strain_rate_per_s", s.strain_rate_interface_per_s},
          {"warnings", p.result.warnings}};
}

json vibration_json(const VibrationAssist& v, const DutyCycle& dc) {
  const double T = dc.period_s;
  json vib = {{"duty_cycle", dc.ratio},
              {"period_s", T},
              {"contact_time_s", dc.ratio * T},
              {"separation_time_s", (1.0 - dc.ratio) * T},
              {"separates", dc.separates}};
  if (v.amplitude_m && !v.duty_cycle) {
    vib["critical_speed_m_per_min"] = units::m_per_s_to_m_per_min(dc.critical_speed_m_per_s);
    vib["rho"] = dc.rho;
    if (dc.separates) {
      vib["separation_phase_deg"] = units::rad_to_deg(dc.separation_phase_rad);
      vib["contact_phase_deg"] = units::rad_to_deg(dc.contact_phase_rad);
    }
  }
  return vib;
  return vib;
}

}  // namespace

json to_json(const io::Case& c, const ForceJobReport& r) {
  const PulsedForces& f = r.forces;
  json oxley;
  if (r.oxley) oxley = oxley_json(c, *r.oxley);
  json vib;
  if (c.vibration) vib = vibration_json(*c.vibration, r.duty_cycle);
  json doc{{"command", "force"},
           {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},
           {"source", c.source},
           {"kc_n_per_mm2", units::pa_to_n_per_mm2(r.kc_pa)},
           {"kf_n_per_mm2", units::pa_to_n_per_mm2(r.kf_pa)},
           {"coefficients", r.oxley ? "oxley" : "given"},
           {"cutting_force_n", f.peak_cutting_n},
           {"thrust_force_n", f.peak_thrust_n},
           {"mean_cutting_force_n", f.mean_cutting_n},
           {"mean_thrust_force_n", f.mean_thrust_n},
           {"duty_cycle", r.duty_cycle.ratio}};
  if (!vib.is_null()) doc["vibration"] = vib;
  if (r.oxley) {
    doc["shear_angle_deg"] = oxley["shear_angle_deg"];
    doc["chip_thickness_mm"] = oxley["chip_thickness_mm"];
    doc["oxley"] = oxley;
  }
  return doc;
}

json json_document(std::string_view command, const io::Case& c) {
  return {{"schema_version", kJsonSchemaVersion},
          {"command", std::string(command)},
          {"source", c.source},
          {"case", io::to_json(c)}};
}

json to_json(const io::Case& c, const TurningSimulationJobReport& job) {
  const TurningSimulationOptions& o = job.options;
  const auto& runs = job.runs;
  using Run = TurningSimulationRun;
  json results = json::array();
  for (const Run& r : runs) {
    const auto& s = r.result;
    // (none when a runaway stopped the run within its first revolution)
    const auto& a = s.revolution_amplitude_m;
    const json first = a.empty() ? json() : json(units::m_to_um(a.front()));
    const json last = a.empty() ? json() : json(units::m_to_um(a.back()));
    results.push_back({{"process", r.name},
                       {"chatter", s.chatter},
                       {"growth_rate_per_s", s.growth_rate_per_s},
                       {"growth_settled", s.growth_settled},
                       {"growth_components", s.growth_components},
                       {"lost_contact", s.lost_contact},
                       {"contact_loss_time_s", s.contact_loss_time_s},
                       {"duty_cycle", s.duty_cycle},
                       {"static_deflection_um", units::m_to_um(s.static_deflection_m)},
                       {"verdict", s.verdict()},
                       {"status", to_string(s.status)},
                       {"stop_time_s", s.stop_time_s},
                       {"first_revolution_amplitude_um", first},
                       {"last_revolution_amplitude_um", last},
                       {"predicted_critical_depth_mm", m_to_mm(r.predicted.boundary.depth_m)},
                       {"step_s", s.step_s},
                       {"steps", s.steps}});
  }
  json doc{{"command", "simulate"},        {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},       {"source", c.source},
           {"spindle_rpm", o.rpm},         {"depth_mm", m_to_mm(o.depth_m)},
           {"feed_mm", m_to_mm(o.feed_m)}, {"duration_s", o.duration_s},
           {"results", std::move(results)}};
  return doc;
}

json to_json(const io::Case& c, const MillingSimulationJobReport& job) {
  const MillingSetup& s = job.setup;
  const MillingSimulationResult& r = job.result;
  const bool s1 = job.s1_law;
  const std::optional<MillingBoundary>& predicted = job.predicted;
  json summary{{"force_pulsation", r.force_pulsation},
               {"cutting_force_pulsation", r.cutting_force_pulsation},
               {"mean_cutting_force_n", r.mean_cutting_force_n},
               {"mean_force_n", r.mean_force_n},
               {"min_force_n", r.min_force_n},
               {"peak_force_n", r.peak_force_n},
               {"mean_fx_n", r.mean_fx_n},
               {"mean_fy_n", r.mean_fy_n},
               {"mean_teeth_in_cut", r.mean_teeth_in_cut},
               {"vibration_pp_x_um", m_to_um(r.vibration_pp_x_m)},
               {"vibration_pp_y_um", m_to_um(r.vibration_pp_y_m)},
               {"chatter_indicator", r.chatter_indicator},
               {"growth_per_period", r.growth_per_period},
               {"growth_rate_per_s", r.growth_rate_per_s},
               {"growth_settled", r.growth_settled},
               {"growth_components", r.growth_components},
               {"status", to_string(r.status)},
               {"stop_time_s", r.stop_time_s},
               {"verdict", r.verdict()},
               {"contact_loss", r.contact_loss},
               {"chatter", r.chatter},
               {"surface_location_error_um",
                r.surface_location_error_m ? json(m_to_um(*r.surface_location_error_m)) : json()},
               {"slices", r.slices},
               {"step_s", r.step_s},
               {"steps", r.steps}};
  if (predicted) summary["predicted_critical_depth_mm"] = m_to_mm(predicted->boundary.depth_m);
  json doc{{"command", "simulate"},
           {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},
           {"source", c.source},
           {"spindle_rpm", s.rpm},
           {"depth_mm", m_to_mm(s.cut.width_m)},
           {"revolutions", s.options.revolutions},
           {"force_law", s1 ? "s1" : "mechanistic"},
           {"summary", std::move(summary)}};
  return doc;
}

json to_json(const io::Case& c, const PlanJobReport& job) {
  const BoreMillingResult& r = job.result;
  json doc{{"command", "plan"},
           {"schema_version", kJsonSchemaVersion},
           {"case", io::to_json(c)},
           {"source", c.source},
           {"q_mm", m_to_mm(r.q_m)},
           {"axial_feed_mm", m_to_mm(r.axial_feed_m)},
           {"max_axial_feed_mm", m_to_mm(r.max_axial_feed_m)},
           {"max_axial_feed_closed_form_mm", m_to_mm(r.max_axial_feed_closed_form_m)},
           {"max_axial_feed_printed_form_mm", m_to_mm(r.max_axial_feed_printed_form_m)},
           {"printed_form_difference_percent", job.printed_form_difference_percent},
           {"inner_depth_mm", m_to_mm(r.inner_depth_m)},
           {"outer_depth_mm", m_to_mm(r.outer_depth_m)},
           {"balanced_offset_mm", m_to_mm(r.balanced_offset_m)},
           {"milling_width_mm", m_to_mm(r.milling_width_m)},
           {"straightness_error_mm", m_to_mm(r.straightness_error_m)},
           {"faceting_mm", m_to_mm(r.faceting_m)},
           {"cutter_rpm", 60.0 * r.cutter_rev_per_s},
           {"workpiece_rpm", 60.0 * r.workpiece_rev_per_s},
           {"feed_per_tooth_mm", m_to_mm(r.feed_per_tooth_m)},
           {"max_chip_thickness_mm", m_to_mm(r.max_chip_thickness_m)},
           {"mean_chip_thickness_mm", m_to_mm(r.mean_chip_thickness_m)},
           {"contact_arc_mm", m_to_mm(r.contact_arc_m)},
           {"chip_width_mm", m_to_mm(r.chip_width_m)},
           {"path_per_edge_m", r.path_per_edge_m},
           {"edge_width_mm", m_to_mm(r.edge_width_m)},
           {"engaged_fraction", r.engaged_fraction},
           {"teeth_in_cut", r.teeth_in_cut},
           {"total_edge_width_mm", m_to_mm(r.total_edge_width_m)},
           {"main_time_min", r.main_time_s / 60.0},
           {"removal_rate_cm3_per_min", r.removal_rate_m3_per_s * 6e7},
           {"offset_mm", m_to_mm(job.chosen.offset_m)},
           {"cutting_speed_m_per_min", 60.0 * job.chosen.cutting_speed_m_per_s},
           {"optimised", job.plan.has_value()},
           {"accuracy_met", r.accuracy_met},
           {"warnings", job.warnings}};
  if (job.plan) doc["binding_constraints"] = job.plan->binding;
  return doc;
}

json to_json(const io::Case& c, const DriveReport& run) {
  json axes = json::array();
  for (const DriveAxisReport& a : run.axes) {
    const FeedDriveResult& d = a.drive;
    axes.push_back(
        {{"axis", a.axis.name},
         {"feed_speed_mm_per_s", 1e3 * a.feed_speed_m_per_s},
         {"commanded_speed_rad_s", d.commanded_speed_rad_s},
         {"mean_load_torque_nm", d.mean_load_torque_nm},
         {"torque_ripple_nm", d.torque_ripple_nm},
         {"mean_speed_rad_s", d.mean_speed_rad_s},
         {"speed_ripple_rad_s", d.speed_ripple_rad_s},
         {"steady_state", d.steady},
         {"steady_from_s", d.steady_from_s},
         {"steady_revolutions", d.steady_periods},
         {"warnings", d.warnings},
         {"k_delta", d.moving ? json(d.k_delta) : json()},
         {"k_delta_verdict", d.moving ? json(to_string(d.k_delta_verdict)) : json()},
         {"static_error", d.moving ? json(d.static_error) : json()},
         {"static_error_ok", d.static_error_ok},
         {"drive_error_um", m_to_um(a.drive_pp_m)},
         {"cutter_error_um", m_to_um(a.cutter_pp_m)},
         {"epsilon_um", m_to_um(a.epsilon_pp_m)},
         {"load_lag_um", d.load_lag_max_m ? json(m_to_um(*d.load_lag_max_m)) : json()},
         {"program_error_um", a.program_error_m ? json(m_to_um(*a.program_error_m)) : json()}});
  }
  json warnings = json::array();
  if (run.chatter) warnings.push_back(chatter_warning(run));
  return {
      {"command", "drive"},     {"schema_version", kJsonSchemaVersion}, {"case", io::to_json(c)},
      {"source", c.source},     {"spindle_rpm", run.cut.rpm},           {"chatter", run.chatter},
      {"verdict", run.verdict}, {"warnings", std::move(warnings)},      {"axes", std::move(axes)}};
}

json to_json(const io::Case& c, const DriveSweepReport& sweep, const std::string& metric) {
  const auto& names = drive_metric_names();
  json points = json::array();
  for (std::size_t i = 0; i < sweep.runs.size(); ++i) {
    json axes = json::array();
    for (const DriveAxisReport& a : sweep.runs[i].axes) {
      json p{
          {"axis", a.axis.name}, {"steady_state", a.drive.steady}, {"warnings", a.drive.warnings}};
      const auto m = drive_metrics(a);
      for (std::size_t k = 0; k < names.size(); ++k)
        p[names[k]] = std::isnan(m[k]) ? json() : json(m[k]);
      axes.push_back(std::move(p));
    }
    points.push_back({{"value", sweep.values[i]},
                      {"chatter", sweep.runs[i].chatter},
                      {"verdict", sweep.runs[i].verdict},
                      {"axes", std::move(axes)}});
  }
  return {{"command", "drive"},         {"schema_version", kJsonSchemaVersion},
          {"case", io::to_json(c)},     {"source", c.source},
          {"sweep", sweep.key},         {"metric", metric},
          {"points", std::move(points)}};
}

json to_json(const EstimateReport& r) {
  json summary{{"schema_version", kJsonSchemaVersion},
               {"command", "monitor estimate"},
               {"format", "cutdyn monitor estimate"},
               {"version", 1},
               {"samples", r.samples},
               {"skipped_lines", r.bad_lines},
               {"force_sigma_n_covers", kSigmaCovers}};
  summary["axes"] = json::object();
  for (const EstimatedAxis& e : r.axes) {
    json a{{"filter", filter_json(e.filter)},
           {"torque_current", r.signed_current
                                  ? "signed: Park transform with rotor_angle_rad"
                                  : "magnitude with the sign of the motion (no rotor_angle_rad)"},
           {"warnings", json::array()}};
    if (e.sign_doubt_samples > 0)
      a["warnings"].push_back({{"kind", "torque-sign"},
                               {"message", kSignDoubt},
                               {"samples", e.sign_doubt_samples},
                               {"first_line", e.sign_doubt_first_line},
                               {"first_time_s", e.sign_doubt_first_time_s}});
    summary["axes"][e.axis] = a;
  }
  return summary;
}

// ---- identify ------------------------------------------------------------------------------

namespace {

// A coefficient: value, and its uncertainty (null without residual degrees of freedom).
json identified_json(const IdentifiedValue& v) {
  const IdentifiedCoefficient& k = v.value;
  const auto known = [&](double x) { return k.uncertainty_known ? json(x) : json(nullptr); };
  return {{"name", v.name},
          {"unit", v.unit},
          {"case_key", v.case_key},
          {"value", k.value},
          {"std_error", known(k.std_error)},
          {"ci95_low", known(k.ci95_low)},
          {"ci95_high", known(k.ci95_high)},
          {"determined", k.determined()},
          {"case_value", v.case_value ? json(*v.case_value) : json(nullptr)}};
}

json identified_sample_json(const IdentifiedSample& s) {
  const MeanForce& m = s.measured;
  json j{{"label", m.label},
         {"feed_per_tooth_mm", m_to_mm(m.feed_per_tooth_m)},
         {"depth_mm", m_to_mm(m.depth_m)},
         {"revolutions", m.revolutions},
         {"fx_n", m.fx_n},
         {"fy_n", m.fy_n},
         {"fitted_fx_n", s.fitted_fx_n},
         {"fitted_fy_n", s.fitted_fy_n},
         {"residual_fx_n", s.residual.fx_n},
         {"residual_fy_n", s.residual.fy_n}};
  if (m.fz_n && s.fitted_fz_n && s.residual.fz_n) {
    j["fz_n"] = *m.fz_n;
    j["fitted_fz_n"] = *s.fitted_fz_n;
    j["residual_fz_n"] = *s.residual.fz_n;
  }
  return j;
}

}  // namespace

json to_json(const io::Case& c, const IdentifyJobReport& r) {
  const CoefficientFit& f = r.fit;
  json doc = json_document("identify", c);
  doc["force_files"] = r.force_files;
  doc["teeth"] = r.cut.teeth;
  doc["entry_deg"] = units::rad_to_deg(r.cut.entry_rad);
  doc["exit_deg"] = units::rad_to_deg(r.cut.exit_rad);
  json coefficients = json::object();
  for (const IdentifiedValue& v : r.values) coefficients[v.key] = identified_json(v);
  doc["coefficients"] = std::move(coefficients);
  json samples = json::array();
  for (const IdentifiedSample& s : r.samples) samples.push_back(identified_sample_json(s));
  doc["samples"] = std::move(samples);
  doc["r_squared"] = {{"x", f.r_squared_x},
                      {"y", f.r_squared_y},
                      {"z", f.r_squared_z ? json(*f.r_squared_z) : json(nullptr)}};
  doc["relative_residual"] = f.relative_residual;
  doc["distinct_feeds"] = f.distinct_feeds;
  doc["degrees_of_freedom"] = f.degrees_of_freedom;
  doc["t_quantile"] = f.degrees_of_freedom > 0 ? json(f.t_quantile) : json(nullptr);
  doc["chip_gain_ratio"] = f.chip_gain_ratio;
  doc["edge_gain_ratio"] = f.edge_gain_ratio;
  doc["notes"] = r.notes;
  doc["warnings"] = r.warnings;
  return doc;
}

json to_json(const FitJobReport& r) {
  const FrfFit& f = r.fit;
  json modes = json::array();
  const auto mode_json = [](const FittedMode& m) {
    return json{{"natural_hz", m.natural_hz},
                {"damping_ratio", m.damping_ratio},
                {"stiffness_n_per_m", m.stiffness_n_per_m},
                {"residue_phase_deg", m.residue_phase_deg},
                {"contribution", m.contribution},
                {"sigma",
                 {{"natural_hz", m.natural_hz_sigma},
                  {"damping_ratio", m.damping_ratio_sigma},
                  {"stiffness_n_per_m", m.stiffness_sigma_n_per_m}}},
                {"covariance", m.covariance}};
  };
  for (const FittedMode& m : f.modes) modes.push_back(mode_json(m));
  json outside = json::array();
  for (const FittedMode& m : f.outside_modes) outside.push_back(mode_json(m));
  json points = json::array();
  for (const StabilisationPoint& p : f.stabilisation)
    points.push_back({{"order", p.order},
                      {"natural_hz", p.natural_hz},
                      {"damping_ratio", p.damping_ratio},
                      {"stable", p.stable}});
  return {{"schema_version", kJsonSchemaVersion},
          {"command", "fit"},
          {"source", r.source},
          {"format", to_string(r.read.format)},
          {"quantity", to_string(r.read.quantity)},
          {"units", r.read.units},
          {"direction", to_string(f.direction)},
          {"band_hz", {f.lo_hz, f.hi_hz}},
          {"points", f.points},
          {"automatic", f.automatic},
          {"modes", std::move(modes)},
          {"outside_modes", std::move(outside)},
          {"noise",
           {{"proportional", f.noise.proportional},
            {"floor_m_per_n", f.noise.floor_m_per_n},
            {"weighted", f.noise_weighted},
            {"coherence_weighted", f.coherence_weighted}}},
          {"rms_relative_error", f.rms_relative_error},
          {"model_rms_relative_error", f.model_rms_relative_error},
          {"converged", f.converged},
          {"stabilisation", std::move(points)},
          {"notes", f.notes},
          {"warnings", r.warnings}};
}

}  // namespace cutdyn::app
