#include "cluttertamp/low/fine.hpp"
#include "low/private.hpp"
#include "cluttertamp/high/up.hpp"
#include "high/private.hpp"
