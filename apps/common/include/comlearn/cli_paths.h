/* comlearn/cli_paths.h - where the comlearn programs find their data and each other (target
 * comlearn_cli).
 *
 * An installed program (PREFIX/bin/comlearn) finds the bundled assets in PREFIX/share/comlearn
 * (rocks/, base/, yumi/) and comlearn-sim beside itself, both located from /proc/self/exe, so an
 * install works wherever it is copied. A program run from the build tree it was built in uses
 * the source tree's assets/ and the build tree's comlearn-sim, as before. The choice: when
 * <exe dir>/COMLEARN_BINDIR_TO_DATADIR/comlearn is a folder the program is installed; otherwise,
 * when it runs from inside COMLEARN_BUILD_DIR, from the build tree; otherwise the installed paths
 * are returned anyway (and the caller's open fails naming them).
 *
 * Each function resolves once and returns a static NUL-terminated string (never NULL). Not
 * thread-safe on first call. */
#ifndef COMLEARN_CLI_PATHS_H
#define COMLEARN_CLI_PATHS_H

/* The assets folder: PREFIX/share/comlearn, or the source tree's assets/. */
const char *cli_paths_assets_dir(void);

/* The YuMi URDF: <assets>/yumi/yumi.urdf. */
const char *cli_paths_yumi_urdf(void);

/* comlearn-sim: beside the running program when installed, else the build tree's. */
const char *cli_paths_sim_exe(void);

#endif
