// The sections of a gearbox document that both schemas share (gears, meshes, shafts, bearings,
// materials, excitation, analysis), read by the loader's Reader (internal to app/config).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "yaml_reader.h"

namespace gearnvh::config {

// A gear's keys (schema 1) plus `extra_keys` (schema 2: shaft, at, mounting).
GearSpec ReadGear(Reader& r, const YAML::Node& n, const std::string& path,
                  const std::map<std::string, Material>& materials,
                  const std::vector<std::string>& extra_keys = {});
StiffnessModel ReadStiffness(Reader& r, const YAML::Node& n, const std::string& path);
std::vector<BearingSpec> ReadBearings(Reader& r, const YAML::Node& n, const std::string& path,
                                      bool required);
// An elastic shaft. Schema 1 places its one gear with `gear_at`; schema 2 places gears with their
// own `at` and lets lumped bodies carry a mass.
std::vector<std::string> ElasticShaftKeys(int schema);
ShaftSpec ReadShaft(Reader& r, const YAML::Node& n, const std::string& path,
                    const std::map<std::string, Material>& materials, int schema = 1);
// Parameters an atlas axis may vary, with their dimension.
const std::map<std::string, Dimension>& AtlasParameters();
SweepRange ReadRange(Reader& r, const YAML::Node& n, const std::string& path, Dimension d);
// An atlas axis of a schema-`schema` document: schema 1 names AtlasParameters(), schema 2 the
// train parameters of config/train_parameters.h (operating.loads[i].torque, meshes[i].backlash
// ...).
AtlasAxis ReadAtlasAxis(Reader& r, const YAML::Node& n, const std::string& path, int schema = 1);
Tier ReadTier(Reader& r, const YAML::Node& map, const std::string& path);
std::map<std::string, Material> ReadMaterials(Reader& r, const YAML::Node& root);
// A mesh's keys plus `extra_keys` (schema 2: gears).
MeshSpec ReadMesh(Reader& r, const YAML::Node& mesh, const std::string& path,
                  const std::vector<std::string>& extra_keys = {});
std::vector<ExcitationOrder> ReadExcitation(Reader& r, const YAML::Node& op, int schema);
// The pitch-line velocity limit on the file's speeds beyond operating.speed: a written
// analysis.speed_sweep and an analysis.atlas axis that varies operating.speed are held to it at
// both ends (RequirePitchLineVelocity, in the unit they were written in). The default sweep is not
// the user's claim: it is clipped to the largest speed allowed instead, and the returned note says
// so ("" when it was within). `speed_unit`: the operating speed's; `velocity_per_speed` and
// `mesh`: the fastest mesh's.
std::string HoldSpeedsToPitchLineLimit(AnalysisSpec& analysis, const SourceLocations& where,
                                       const DisplayUnit& speed_unit, double velocity_per_speed,
                                       const std::string& mesh);

AnalysisSpec ReadAnalysis(Reader& r, const YAML::Node& root, int schema = 1);
// The schema version a document declares (1 when absent): 1 or 2, else InputError.
int SchemaOf(Reader& r, const YAML::Node& root);

}  // namespace gearnvh::config
