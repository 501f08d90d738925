/* liggghts-poly: the stock LIGGGHTS front end with the polyhedral styles.
 * Same command-line switches as `liggghts` (-in -var -log -screen -echo
 * -suffix ...), since they are parsed by LAMMPS' own constructor. */
#include <mpi.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lammps.h"
#include "input.h"
#include "signal_handling.h"

#include "polyhedral_register.h"

using namespace LAMMPS_NS;

// LIGGGHTS prints its -help in the LAMMPS constructor and exits there; the
// polyhedral styles follow it from an exit handler.
static void print_polyhedral_styles(void)
{
  polyhedral_print_styles(stdout);
  fflush(stdout);
}

// `-screen none` leaves LIGGGHTS' screen pointer NULL, and some of its own code prints to it unguarded (fix
// insert/pack's region set-up, Region::reset_random, crashes on the first run): the same silence through
// /dev/null never crashes.
static void silence_screen_safely(int argc, char **argv)
{
  static char null_device[] = "/dev/null";
  for (int a = 1; a < argc; a++)  /* with partitions LIGGGHTS opens <screen>.<N>: left as it is */
    if (strcmp(argv[a], "-partition") == 0 || strcmp(argv[a], "-p") == 0) return;
  for (int a = 1; a + 1 < argc; a++)
    if ((strcmp(argv[a], "-screen") == 0 || strcmp(argv[a], "-sc") == 0) && strcmp(argv[a + 1], "none") == 0)
      argv[a + 1] = null_device;
}

int main(int argc, char **argv)
{
  // Same signal behaviour as `liggghts`: SIGINT/SIGTERM ask for a clean stop,
  // SIGUSR1 for a restart file.
  struct sigaction quit_action, restart_action;
  memset(&quit_action, 0, sizeof quit_action);
  memset(&restart_action, 0, sizeof restart_action);
  quit_action.sa_handler = SignalHandler::int_handler;
  restart_action.sa_handler = SignalHandler::usr1_handler;
  sigaction(SIGINT, &quit_action, NULL);
  sigaction(SIGTERM, &quit_action, NULL);
  sigaction(SIGUSR1, &restart_action, NULL);

  // Error::one() aborts without flushing: line buffering keeps its ERROR line
  // when the screen is a pipe (mpirun, batch systems, tests).
  setvbuf(stdout, NULL, _IOLBF, 0);

  MPI_Init(&argc, &argv);
  if (!polyhedral_verify_hooks()) MPI_Abort(MPI_COMM_WORLD, 1);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  for (int a = 1; a < argc && rank == 0; a++)
    if (strcmp(argv[a], "-h") == 0 || strcmp(argv[a], "-help") == 0) {
      atexit(print_polyhedral_styles);
      break;
    }

  silence_screen_safely(argc, argv);
  LAMMPS *lammps = new LAMMPS(argc, argv, MPI_COMM_WORLD);
  lammps->input->file();
  delete lammps;

  MPI_Finalize();
  return 0;
}
