#pragma once
#include "cluttertamp/low/fine.hpp"
