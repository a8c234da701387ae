/* main.c - pomlab: dispatch to the subcommands. Built twice (cli/CMakeLists.txt):
 * pomlab-full runs every command; pomlab (POM_CLI_LIGHT) runs the kinematic
 * commands itself and executes its sibling pomlab-full for the others, so that
 * model, ik, fk and workspace never load HDF5, SUNDIALS, NLopt and their
 * dependencies (bench/README.md, start-up). */
#if POM_CLI_LIGHT
#define _POSIX_C_SOURCE 200809L /* readlink, execv */
#endif
#include "pom_arch_file.h"
#include "pom_cli.h"
#include "pom_version.h"
#if !POM_CLI_LIGHT
#include "pom_h5.h"
#endif

#include <errno.h>
#include <stdio.h>
#include <string.h>
#if POM_CLI_LIGHT
#include <unistd.h>
#endif

typedef struct {
  const char *name;
  pom_cli_fn fn;
  const char *summary;
} command;

/* The commands that need the dynamics, optimization or HDF5 libraries: in
 * the light program, NULL (run by pomlab-full). */
#if POM_CLI_LIGHT
#define HEAVY(fn) NULL
#else
#define HEAVY(fn) fn
#endif

/* One line per subcommand; each lives in cli/cmd_<name>.c. */
static const command commands[] = {
    {.name = "model",
     .fn = pom_cmd_model,
     .summary = "the resolved mechanism: bodies, joints, actuators (SI, home pose)"},
    {.name = "ik",
     .fn = pom_cmd_ik,
     .summary = "inverse kinematics of a ZYX Euler orientation: q, J, kappa, limits"},
    {.name = "fk",
     .fn = pom_cmd_fk,
     .summary = "forward kinematics of actuator displacements: orientation"},
    {.name = "workspace",
     .fn = pom_cmd_workspace,
     .summary = "regular dexterous workspace, GCI, dexterity map"},
    {.name = "simulate",
     .fn = HEAVY(pom_cmd_simulate),
     .summary = "one maneuver: settling times, energies, traces"},
    {.name = "tune",
     .fn = HEAVY(pom_cmd_tune),
     .summary = "PID gains by one criterion for every architecture"},
    {.name = "montecarlo",
     .fn = HEAVY(pom_cmd_montecarlo),
     .summary = "N random maneuvers of one mechanism: time and energy"},
    {.name = "study",
     .fn = HEAVY(pom_cmd_study),
     .summary = "candidates x maneuvers: results file, tables, verdict, figures"},
    {.name = "synth",
     .fn = HEAVY(pom_cmd_synth),
     .summary = "kinematic synthesis: response surfaces, desirability, scaling"},
    {.name = "sensitivity",
     .fn = HEAVY(pom_cmd_sensitivity),
     .summary = "Sobol indices / Morris effects of uncertain parameters"},
    {.name = "tradeoff",
     .fn = HEAVY(pom_cmd_tradeoff),
     .summary = "speed against accuracy: solver and model fidelity sweep"},
    {.name = "capability",
     .fn = HEAVY(pom_cmd_capability),
     .summary = "peak rates and accelerations over the workspace, slew times"},
    {.name = "codesign",
     .fn = HEAVY(pom_cmd_codesign),
     .summary = "geometry, actuator size and gains together: fronts, ranking at each one's best"},
    {.name = "view",
     .fn = HEAVY(pom_cmd_view),
     .summary = "the mechanism in 3-D in a browser page; --png, --mp4"},
    {.name = "export",
     .fn = pom_cmd_export,
     .summary = "the mechanism for another program: MuJoCo MJCF (--mjcf)"},
    {.name = "gradient",
     .fn = HEAVY(pom_cmd_gradient),
     .summary = "design gradients of the maneuver metrics (forward sensitivities)"},
    {.name = NULL, .fn = NULL, .summary = NULL} /* end */
};

#if POM_CLI_LIGHT
/* Replaces this process by pomlab-full from this program's directory with the
 * same arguments; returns only on failure (exit code 1, reason printed). */
static int run_full(char **argv) {
  char path[4096];
  ssize_t len = readlink("/proc/self/exe", path, sizeof path - 32);
  if (len <= 0 || (size_t)len >= sizeof path - 32) {
    fprintf(stderr, "pomlab: cannot find this program's path: %s\n", strerror(errno));
    return 1;
  }
  path[len] = '\0';
  char *slash = strrchr(path, '/');
  strcpy(slash ? slash + 1 : path, "pomlab-full");
  execv(path, argv);
  fprintf(stderr, "pomlab: cannot run %s: %s\n", path, strerror(errno));
  return 1;
}
#endif

static void usage(FILE *out) {
  fprintf(out, "usage: pomlab COMMAND CONFIG [options]   (pomlab COMMAND --help for details)\n\n"
               "Design study toolkit for 3-DOF parallel orientation manipulators.\n\n"
               "commands:\n");
  for (size_t k = 0; commands[k].name; ++k)
    fprintf(out, "  %-12s %s\n", commands[k].name, commands[k].summary);
  fprintf(out, "\n  --version  print version, git commit and where the plotting scripts are\n");
}

int main(int argc, char **argv) {
  if (argc < 2) {
    usage(stderr);
    return 2;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
    usage(stdout);
    return 0;
  }
  if (strcmp(argv[1], "--version") == 0) {
    char scripts[1024];
    int found = pom_cli_scripts_dir(scripts, sizeof scripts) == 0;
    printf("pomlab %s (commit %s)\nscripts: %s%s\n", POM_VERSION, POM_GIT_COMMIT, scripts,
           found ? "" : " (not found: no figures)");
    return 0;
  }
  for (size_t k = 0; commands[k].name; ++k)
    if (strcmp(argv[1], commands[k].name) == 0) {
#if POM_CLI_LIGHT
      if (!commands[k].fn) return run_full(argv);
#endif
      /* the architecture files: the catalog and $POMLAB_ARCHITECTURES
       * (docs/architecture-files.md section 4), registered before any
       * config is read */
      pom_error aerr;
      pom_error_clear(&aerr);
      if (pom_arch_files_register_all(&aerr) != POM_OK) {
        fprintf(stderr, "pomlab: architecture files: %s\n", aerr.message);
        return 2;
      }
#if !POM_CLI_LIGHT
      /* a file that failed to close must not crash HDF5's exit handler */
      pom_h5_startup();
#endif
      int rc = commands[k].fn(argc - 1, argv + 1);
#if !POM_CLI_LIGHT
      pom_h5_shutdown();
#endif
      /* tables and JSON on a full disk or a closed pipe are a failure too */
      if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "pomlab: %s: writing standard output failed: %s\n", argv[1],
                strerror(errno));
        if (rc == 0) rc = 1;
      }
      return rc;
    }
  fprintf(stderr, "pomlab: unknown command '%s'\n\n", argv[1]);
  usage(stderr);
  return 2;
}
