#pragma once
// The watchdog of a run under mpirun (docs/scale.md, "Stopped ranks"). Every rank sends a sign
// of life from a thread of its own several times per timeout (rank 0 to every other rank, the
// others to rank 0). When a rank has been silent for the timeout (stopped by SIGSTOP, a hung
// node), the rank watching it prints
//   microbrdf <command>: error: --mpi-timeout: MPI rank R (pid P on HOST) has not responded for T
//   (stopped or hung); every rank was ended
// and ends every rank (MPI_Abort, exit code 1), so mpirun never waits for ever. A rank busy
// computing still answers: the timeout does not bound the length of a job. MpiSession
// (distribute.hpp) starts and stops it; nothing happens in a plain run.
#include <string>

namespace microbrdf {

/// 30 minutes: far longer than any pause of a healthy rank (a swap storm, a busy file system).
inline constexpr double kDefaultMpiTimeoutSeconds = 1800;

/// Sets the timeout in seconds (`--mpi-timeout`); 0 turns the watchdog off.
void mpi_set_timeout(double seconds);
double mpi_timeout();
/// The command the message names ("ndf" gives "microbrdf ndf: error: ...").
void mpi_set_command(const std::string& command);

}  // namespace microbrdf
