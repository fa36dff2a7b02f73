# The rooms of the generator and their one-way doors: one folder and one library (cs_<stage>) per
# stage. CS_LAYER_<stage> names the stages a stage uses directly; it may also use what those use,
# and nothing else. The libraries link by this table (generator/CMakeLists.txt) and
# check_layers.cmake fails the build when a source #includes a stage outside it (a wrong-way door).
# docs/architecture.md draws the picture.
#
#   cli -+-> pipeline -> output -> job -+-> struts -+-> tree -+-> overhang -> query -> mesh -> core
#        |      |          |            |           +-> ceilings -+
#        |      |          |            +-> orient ---------+
#        |      +----------+-> render -> core
#        +-> edit -> job
#        +-> check -> query -> mesh -> core
#        +-> view -> pipeline, check, edit      (`clever-support view`: the page's server)
set(CS_LAYERS core mesh query overhang ceilings orient tree struts job render output pipeline check edit view cli)

set(CS_LAYER_core "")                   # geometry, parameters and their table, rules, errors
set(CS_LAYER_mesh core)                 # read/write meshes, repair, place on the bed
set(CS_LAYER_query mesh)                # the model index: rays, distances, inside tests (CGAL)
set(CS_LAYER_overhang query)            # overhang samples
set(CS_LAYER_ceilings overhang)         # walls under ceilings low over the bed or a floor
set(CS_LAYER_orient overhang)           # the pose needing least support (scored by a callback)
set(CS_LAYER_tree overhang)             # leaves, tips and pillars, the grown tree
set(CS_LAYER_struts tree ceilings)      # widths, bodies, the support solid (struts and walls)
set(CS_LAYER_job struts orient)         # Job (what the user asked) and Result (what a run computed)
set(CS_LAYER_render core)               # OpenSCAD on the command line
set(CS_LAYER_output job render)         # STL, 3MF, report, parametric .scad
set(CS_LAYER_pipeline output)           # run_job: one call through every stage
set(CS_LAYER_check query)               # judges a supported model, independent of the generator
set(CS_LAYER_edit job)                  # reads an edited .scad back into a Job
set(CS_LAYER_view pipeline check edit)  # `clever-support view`: serves the page, makes its edits
set(CS_LAYER_cli pipeline check edit view)  # the command line
