/* main.c - pomlab: dispatch to the subcommands. */
#include "pom_cli.h"
#include "pom_version.h"

#include <stdio.h>
#include <string.h>

typedef struct {
  const char *name;
  pom_cli_fn fn;
  const char *summary;
} command;

/* One line per subcommand; each lives in cli/cmd_<name>.c. */
static const command commands[] = {
    {"model", pom_cmd_model, "the resolved mechanism: bodies, joints, actuators (SI, home pose)"},
    {"ik", pom_cmd_ik, "inverse kinematics of a ZYX Euler orientation: q, J, kappa, limits"},
    {"fk", pom_cmd_fk, "forward kinematics of actuator displacements: orientation"},
    {"workspace", pom_cmd_workspace, "regular dexterous workspace, GCI, dexterity map"},
    {"simulate", pom_cmd_simulate, "one maneuver: settling times, energies, traces"},
    {"tune", pom_cmd_tune, "PID gains by one criterion for every architecture"},
    {"montecarlo", pom_cmd_montecarlo, "N random maneuvers of one mechanism: time and energy"},
    {"study", pom_cmd_study, "candidates x maneuvers: results file, tables, verdict, figures"},
    {"synth", pom_cmd_synth, "kinematic synthesis: response surfaces, desirability, scaling"},
    {"tradeoff", pom_cmd_tradeoff, "speed against accuracy: solver and model fidelity sweep"},
    {NULL, NULL, NULL} /* end */
};

static void usage(FILE *out) {
  fprintf(out, "usage: pomlab COMMAND CONFIG [options]   (pomlab COMMAND --help for details)\n\n"
               "Design study toolkit for 3-DOF parallel orientation manipulators.\n\n"
               "commands:\n");
  for (size_t k = 0; commands[k].name; ++k)
    fprintf(out, "  %-10s %s\n", commands[k].name, commands[k].summary);
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
    if (strcmp(argv[1], commands[k].name) == 0) return commands[k].fn(argc - 1, argv + 1);
  fprintf(stderr, "pomlab: unknown command '%s'\n\n", argv[1]);
  usage(stderr);
  return 2;
}
