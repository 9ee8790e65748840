// pmu_wake_timer: timing signal St and the output window of the second sensor supply.
//
// Power control unit 56 issues St at the start of each intermittent output ([0336]); supply
// unit 54 then outputs Vs2 for Wt = Pw + Pi + Ps ([0318]-[0323], [0347]); the comparators are
// sampled during Ps, at its last tick (I3, [0354]). With the key on Vs2 is continuous and the
// comparators are sampled every SMP_ON ticks ([0349], I4). Spec 2.2.
//
// One free-running 16-bit timer; every output is decoded from registers only (Moore, spec 1).

module pmu_wake_timer import pmu50_alt_pkg::*; (
  input  logic        clk,
  input  logic        rst_n,
  input  logic        key_on_i,       // Sig (registered)
  input  logic        key_rise_i,     // kon: restart
  input  logic        key_fall_i,     // koff: restart, first St at once (spec 3)
  input  logic [15:0] interval_i,     // drive interval Si, ticks (registered, 56b)
  input  cfg_t        cfg_i,          // parameters in force (registered)
  output logic        st_o,
  output logic        vs2_en_o,
  output logic        ps_win_o,
  output logic        smp_o
);

  logic [15:0] timer_q, timer_d;
  logic [16:0] timer_inc;             // timer + 1 without wrap
  logic [17:0] wt;
  logic [16:0] ps_start;
  logic [15:0] cycle_len;
  logic        cycle_end;

  assign timer_inc = {1'b0, timer_q} + 17'd1;
  assign wt        = cfg_window(cfg_i);
  assign ps_start  = cfg_ps_start(cfg_i);

  // Output decode (spec 2.2 table).
  always_comb begin
    if (key_on_i) begin
      st_o     = 1'b0;
      vs2_en_o = 1'b1;
      ps_win_o = 1'b0;
      smp_o    = (timer_inc == {1'b0, cfg_i.smp_on});
    end else begin
      st_o     = (timer_q == '0);
      vs2_en_o = ({2'b00, timer_q} < wt);
      ps_win_o = ({1'b0, timer_q} >= ps_start) && ({2'b00, timer_q} < wt);
      smp_o    = ({1'b0, timer_inc} == wt);              // last tick of Ps
    end
  end

  // Cycle length: Si while off, SMP_ON while on. `>=` so that a cycle always ends.
  assign cycle_len = key_on_i ? cfg_i.smp_on : interval_i;
  assign cycle_end = (timer_inc >= {1'b0, cycle_len});

  always_comb begin
    timer_d = timer_inc[15:0];
    if (key_rise_i || key_fall_i || cycle_end) begin
      timer_d = '0;
    end
  end

  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      timer_q <= '0;
    end else begin
      timer_q <= timer_d;
    end
  end

endmodule : pmu_wake_timer
