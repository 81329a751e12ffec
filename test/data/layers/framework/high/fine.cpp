#include "cluttertamp/low/fine.hpp"
#include "cluttertamp/high/up.hpp"
#include "high/private.hpp"
#include <vector>
