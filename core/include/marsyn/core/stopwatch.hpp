#pragma once
// Core's stages time themselves with the one Stopwatch that plugins use too; this name stays for
// the files that still include it.
#include "marsyn/stopwatch.hpp"
