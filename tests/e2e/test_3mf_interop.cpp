// 3MF written by another program: PrusaSlicer arranges two of the bundled examples on one plate
// and exports the project as 3MF (objects placed by build item transforms, its own metadata
// parts); the reader (mesh/read_3mf.hpp) gets both, with their triangles and volumes, as one model.
// Skips when prusa-slicer is not installed.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "mesh/mesh_io.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

TEST(ThreeMfInterop, APrusaSlicerPlateOfTwoObjectsReadsAsBoth) {
    if (run("command -v prusa-slicer").code != 0)
        GTEST_SKIP() << "prusa-slicer is not installed (scripts/install-deps.sh installs it)";
    TempDir t;
    const std::string arches = source_dir() + "/examples/models/arches.stl";
    const std::string bird = source_dir() + "/examples/models/bird.stl";
    test::Run r = run("prusa-slicer --datadir " + quote(t / "datadir") + " --loglevel 1 --merge --export-3mf -o " +
                quote(t / "plate.3mf") + " " + quote(arches) + " " + quote(bird));
    ASSERT_EQ(r.code, 0) << r.out;

    std::string contents;
    const Mesh plate = read_mesh(t / "plate.3mf", false, &contents);
    const Mesh a = read_mesh(arches), b = read_mesh(bird);
    EXPECT_EQ(plate.faces.size(), a.faces.size() + b.faces.size());
    EXPECT_NEAR(signed_volume(plate), signed_volume(a) + signed_volume(b), 1e-4 * (signed_volume(a) + signed_volume(b)));
    EXPECT_NE(contents.find("2 build items of 2 objects"), std::string::npos) << contents;
    // Both stand on the bed, as PrusaSlicer placed them: the transforms were applied, not dropped.
    const Box3 box = bounding_box(plate);
    EXPECT_NEAR(box.min.z, 0, 1e-3);
    EXPECT_NEAR(box.max.z, std::max(bounding_box(a).max.z, bounding_box(b).max.z), 1e-3);
}

}  // namespace
}  // namespace cs::test
