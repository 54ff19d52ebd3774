/*
 * sim.h -- the simulation layer, all of it: scenario files, the flight and
 * the air it meets, the ship's motion, the pilot station, the world a
 * flight flies in, the pilot interface and the one flight runner, the
 * real-time loop and its LCM side, task files, the automated and replay
 * pilots, and the run's LCM log. Each part has its own header (sim_*.h,
 * included here); a file may include only the part it uses.
 */
#ifndef DISIM_SIM_H
#define DISIM_SIM_H

#include "sim_scenario.h"
#include "sim_flight.h"
#include "sim_ship_motion.h"
#include "sim_station.h"
#include "sim_world.h"
#include "sim_runner.h"
#include "sim_loop.h"
#include "sim_task.h"
#include "sim_log.h"
#include "sim_pilot.h"
#include "sim_ios.h"

#endif
