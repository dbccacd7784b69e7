/* The simulator library in one include: scenes, the engine (one position at
 * a time, for the emulated board), whole scans and truth, trace measures. */
#ifndef UWBSIM_UWBSIM_H
#define UWBSIM_UWBSIM_H

#include "bound.h"
#include "engine.h"
#include "measure.h"
#include "scene.h"
#include "simulate.h"
#include "surfaces.h"

#endif
