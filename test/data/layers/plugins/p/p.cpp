#include "cluttertamp/high/up.hpp"
#include "low/private.hpp"
