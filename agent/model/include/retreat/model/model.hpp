#pragma once
/// @file
/// Everything in retreat::model: the paper's equations.

#include "retreat/model/control.hpp"
#include "retreat/model/ctmc.hpp"
#include "retreat/model/encounter.hpp"
#include "retreat/model/estimation.hpp"
#include "retreat/model/optimum.hpp"
#include "retreat/model/params.hpp"
