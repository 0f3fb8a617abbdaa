# Precompiled headers for the targets of many translation units. Most of slipfit's units spend
# most of their compile time parsing Eigen and PCL (3.1 of 3.3 s for one of the stages with -O3;
# 8 of 13 s for a segmentation test, gtest and PCL's point types included): parsed once per
# target, a unit loads them in a fraction of a second. The lists name what most units of each
# target include anyway; a unit still includes what it uses (-DSLIPFIT_PRECOMPILE_HEADERS=OFF
# builds every unit on its own includes).
set(SLIPFIT_PCH_LIBRARY
  <algorithm> <array> <cmath> <cstdint> <functional> <limits> <memory> <optional> <string>
  <string_view> <utility> <vector>
  <Eigen/Core> <Eigen/Eigenvalues> <Eigen/Geometry>
  <pcl/point_cloud.h> <pcl/point_types.h>)
set(SLIPFIT_PCH_TESTS ${SLIPFIT_PCH_LIBRARY}
  <filesystem> <fstream> <iostream> <map> <random> <set> <sstream>
  <pcl/PCLPointCloud2.h> <gtest/gtest.h>)

# slipfit_precompile(TARGET LIST [more headers...]): TARGET's units start from the headers of
# LIST (a variable name) and the ones after it.
function(slipfit_precompile target list)
  if(SLIPFIT_PRECOMPILE_HEADERS)
    target_precompile_headers(${target} PRIVATE ${${list}} ${ARGN})
  endif()
endfunction()
