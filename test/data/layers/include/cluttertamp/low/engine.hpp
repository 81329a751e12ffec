#pragma once
#include <fcl/narrowphase/collision.h>
