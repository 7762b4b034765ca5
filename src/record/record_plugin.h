/* The record library's plugin table (libvoussoir-record): what the program calls through it
 * after loading it with dlopen (src/plugin/plugin.h). */
#ifndef VS_RECORD_PLUGIN_H
#define VS_RECORD_PLUGIN_H

#include "plugin_head.h"
#include "sweep_rows.h"
#include "voussoir/output.h"

/* libvoussoir-record: exported as vs_record_plugin_table. */
typedef struct {
  vs_plugin_head head;
  void (*output_opts_default)(vs_output_opts *o);
  vs_status (*output_create)(const char *path, const vs_run *run, const char *case_text,
                             const vs_output_opts *opts, vs_output **out, vs_error *err);
  int (*output_sample)(void *user, const vs_run *run, const vs_run_sample *s);
  int (*output_event)(void *user, const vs_run *run, const vs_run_event *e);
  void (*output_interrupt)(vs_output *o);
  vs_status (*output_finish)(vs_output *o, const vs_run *run, vs_status run_status,
                             const vs_error *run_err, vs_error *err);
  const vs_error *(*output_error)(const vs_output *o);
  long (*output_rows)(const vs_output *o);
  const char *(*output_xdmf_path)(const vs_output *o);
  int (*output_xdmf_written)(const vs_output *o);
  char *(*output_xdmf_path_for)(const char *h5_path);
  void (*output_destroy)(vs_output **o);
  void (*output_process_init)(void);
  void (*output_process_end)(int clean);
  vs_status (*sweep_summary_h5)(const char *dir, const vs_sweep_axis *ax, int nax,
                                const vs_sweep_row *rows, int n, vs_error *err);
} vs_record_plugin;

#endif
