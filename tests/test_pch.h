// The precompiled header every test program shares (tests/CMakeLists.txt).
//
// Why: the test programs are most of CI's compile time, and each one parsed
// GoogleTest, Eigen and the simulation's headers on its own (about 4.7 s of
// a 7.7 s compile of tests/dem_core/test_free_fall.cpp at -O2 on this
// machine; 3.5 s with this header precompiled). Only headers that nearly
// every test includes belong here: the list changes no test's meaning, only
// how often the compiler reads these files.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "dem_core/simulation.h"
