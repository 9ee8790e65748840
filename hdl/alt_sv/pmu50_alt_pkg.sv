// pmu50_alt_pkg: shared constants and types of the alternative PMU 50 core.
//
// Sources: docs/spec.md section 2.8 (register map, STATUS bits), section 2.6 (FIG. 17/18 path
// encodings), section 4 (legal parameter values). Patent US 2022/0041215 A1: [0259] (T1, T2,
// x, minimum, Cth are set per device), [0321]-[0323] (Pw, Pi, Ps programmable), [0349]
// (on-key sampling period).

package pmu50_alt_pkg;

  // ---------------------------------------------------------------------------------------------
  // Register map (spec 2.8). 8-bit address, 16-bit data.
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned BusAw = 8;
  localparam int unsigned BusDw = 16;

  localparam logic [BusAw-1:0] ADDR_ID      = 8'h00;  // RO 0x5050
  localparam logic [BusAw-1:0] ADDR_VERSION = 8'h01;  // RO 0x0001
  localparam logic [BusAw-1:0] ADDR_CTRL    = 8'h02;  // RW bit 0 adaptive ([0214], [0083])
  localparam logic [BusAw-1:0] ADDR_PW      = 8'h03;  // RW waiting period Pw ([0321])
  localparam logic [BusAw-1:0] ADDR_PI      = 8'h04;  // RW idle period Pi ([0322])
  localparam logic [BusAw-1:0] ADDR_PS      = 8'h05;  // RW sampling period Ps ([0322])
  localparam logic [BusAw-1:0] ADDR_SI_MAX  = 8'h06;  // RW maximum interval x ([0216])
  localparam logic [BusAw-1:0] ADDR_SI_MIN  = 8'h07;  // RW minimum interval ([0228])
  localparam logic [BusAw-1:0] ADDR_T1      = 8'h08;  // RW shortening step ([0224])
  localparam logic [BusAw-1:0] ADDR_T2      = 8'h09;  // RW expanding step ([0250])
  localparam logic [BusAw-1:0] ADDR_CTH     = 8'h0A;  // RW count threshold, 8 bit ([0250])
  localparam logic [BusAw-1:0] ADDR_SMP_ON  = 8'h0B;  // RW on-key sampling period ([0349])
  localparam logic [BusAw-1:0] ADDR_CFG     = 8'h0C;  // RO [2:0] SYNC_DEPTH, [12:8] CNT_W
  localparam logic [BusAw-1:0] ADDR_CNT_S   = 8'h10;  // RO CNTs sign-extended
  localparam logic [BusAw-1:0] ADDR_CNT_C   = 8'h11;  // RO CNTc sign-extended
  localparam logic [BusAw-1:0] ADDR_CNT_R   = 8'h12;  // RO CNTr
  localparam logic [BusAw-1:0] ADDR_SI      = 8'h13;  // RO current drive interval
  localparam logic [BusAw-1:0] ADDR_STATUS  = 8'h14;  // RO / W1C (bits 5 and 9)

  localparam logic [BusDw-1:0] ID_VALUE      = 16'h5050;
  localparam logic [BusDw-1:0] VERSION_VALUE = 16'h0001;

  // STATUS (0x14) bit positions, spec 2.8.
  localparam int unsigned STATUS_CS        = 0;
  localparam int unsigned STATUS_CC        = 1;
  localparam int unsigned STATUS_HIST_S    = 2;
  localparam int unsigned STATUS_HIST_C    = 3;
  localparam int unsigned STATUS_DIAG      = 4;
  localparam int unsigned STATUS_QSKIP     = 5;  // W1C
  localparam int unsigned STATUS_SIG       = 6;
  localparam int unsigned STATUS_VLD       = 7;
  localparam int unsigned STATUS_SR        = 8;
  localparam int unsigned STATUS_BUS_ERR   = 9;  // W1C

  // ---------------------------------------------------------------------------------------------
  // The programmable parameter set (spec 2.8, registers 0x02-0x0B), one packed word.
  // ---------------------------------------------------------------------------------------------
  typedef struct packed {
    logic        adaptive;  // CTRL[0]: FIG. 17/18 adaptive interval, else fixed cycle T = x
    logic [15:0] pw;        // waiting period Pw, ticks [0321]
    logic [15:0] pi;        // idle period Pi, ticks [0322]
    logic [15:0] ps;        // sampling period Ps, ticks [0322]
    logic [15:0] si_max;    // maximum interval x, ticks [0216], [0226]
    logic [15:0] si_min;    // minimum interval, ticks [0228]
    logic [15:0] t1;        // shortening step T1, ticks [0224]
    logic [15:0] t2;        // expanding step T2, ticks [0250]
    logic [7:0]  cth;       // count threshold Cth [0250]
    logic [15:0] smp_on;    // on-key sampling period, ticks [0349]
  } cfg_t;

  // Patent defaults at a 10 us clock (spec 2.8 reset column).
  localparam cfg_t CFG_DEFAULT = '{
    adaptive: 1'b1,
    pw:       16'd5,
    pi:       16'd12,
    ps:       16'd5,
    si_max:   16'd660,
    si_min:   16'd220,
    t1:       16'd220,
    t2:       16'd110,
    cth:      8'd4,
    smp_on:   16'd10
  };

  // ---------------------------------------------------------------------------------------------
  // FIG. 17 / FIG. 18 path encodings (spec 2.6). These are observable encodings: keep the values.
  // ---------------------------------------------------------------------------------------------
  typedef enum logic [2:0] {
    F17_IDLE       = 3'd0,  // no key-off sampling strobe
    F17_S1_NO_RISE = 3'd1,  // S1: N, Vs2 did not rise ([0264])
    F17_S5_AT_MIN  = 3'd2,  // S4, S5: Y ([0282])
    F17_S6_SHORTEN = 3'd3,  // S4, S5: N, S6 ([0260]-[0262])
    F17_S7_AT_MAX  = 3'd4,  // S7: Y ([0285])
    F17_S9_COUNT   = 3'd5,  // S8: N, S9 ([0248])
    F17_S10_EXPAND = 3'd6,  // S8: Y, S10, S11, S9 ([0250], [0291])
    F17_FIXED      = 3'd7   // adaptive = 0: fixed cycle T = x ([0083])
  } fig17_e;

  typedef enum logic [2:0] {
    F18_IDLE           = 3'd0,  // detection not run
    F18_S23_DET_CS     = 3'd1,  // S20: Y, S21: N, S22, S23
    F18_S21_CS_REPEAT  = 3'd2,  // S20: Y, S21: Y, S24
    F18_S28_DET_CC     = 3'd3,  // S20: N, S25: Y, S26: N, S27, S28
    F18_S26_CC_REPEAT  = 3'd4,  // S20: N, S25: Y, S26: Y, S24
    F18_S25_NO_CHANGE  = 3'd5   // S20: N, S25: N, S24
  } fig18_e;

  // ---------------------------------------------------------------------------------------------
  // Helpers
  // ---------------------------------------------------------------------------------------------

  // The helpers read a few fields of the set only.
  /* verilator lint_off UNUSEDSIGNAL */

  // Output window Wt = Pw + Pi + Ps ([0320]), 18 bits so that it never wraps.
  function automatic logic [17:0] cfg_window(cfg_t c);
    return {2'b00, c.pw} + {2'b00, c.pi} + {2'b00, c.ps};
  endfunction

  // Start of Ps inside the window: Pw + Pi, 17 bits.
  function automatic logic [16:0] cfg_ps_start(cfg_t c);
    return {1'b0, c.pw} + {1'b0, c.pi};
  endfunction

  /* verilator lint_on UNUSEDSIGNAL */

  // Legality of a parameter set, spec section 4. The register bank refuses a write that would
  // make the set illegal, so the registers always hold a legal set.
  function automatic logic cfg_is_legal(cfg_t c);
    logic        ok;
    logic [15:0] shortest;
    ok = 1'b1;
    // No zero periods; Cth in 1..255.
    if (c.ps == '0 || c.si_max == '0 || c.si_min == '0) ok = 1'b0;
    if (c.t1 == '0 || c.t2 == '0 || c.smp_on == '0)      ok = 1'b0;
    if (c.cth == '0)                                     ok = 1'b0;
    // Pw + Pi >= 1: the sample must come at least a tick after Vs2 rises ([0321]).
    if (cfg_ps_start(c) == '0)                           ok = 1'b0;
    // minimum <= x ([0228]).
    if (c.si_min > c.si_max)                             ok = 1'b0;
    // Wt below the shortest interval: Vs2 must switch off between two pulses ([0319]).
    shortest = c.adaptive ? c.si_min : c.si_max;
    if (cfg_window(c) >= {2'b00, shortest})              ok = 1'b0;
    return ok;
  endfunction

endpackage : pmu50_alt_pkg
