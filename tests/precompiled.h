// Parsed once per build and given to every test file (tests/CMakeLists.txt): the headers most
// test files include. Parsing them took about 40 % of compiling a test file in the sanitizer
// build. Each test file still includes what it uses, so it compiles without this header too.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "model/material.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "scene/scene_loader.h"
