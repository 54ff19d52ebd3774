/* cmds.h -- the disim subcommands: int cmd_NAME(argc, argv), argv[0] being
 * the subcommand's name; exit status 0 ok, 1 failure or bad input, 2 usage. */
#ifndef DISIM_APP_CMDS_H
#define DISIM_APP_CMDS_H

int cmd_render(int argc, char **argv);
int cmd_airwaked(int argc, char **argv);
int cmd_shol(int argc, char **argv);

#endif
