// The coverage monitor's internal inputs rebuilt from the contract ports of `pmu50`
// (docs/signals.md) and its parameters, as docs/spec.md defines them: what the coverage proofs
// (hdl/formal/pmu50_formal/bind.py) give the monitor for an internal that the RTL's map does not
// name. The same rebuilding as the shadows of the property kit (pmu50_formal.sv): the key
// through SYNC_DEPTH flops (spec 2.1), the parameter registers as the bus wrote them while
// sig = 1 and the write was legal (spec 2.8, 4), the timer (spec 2.2), "a sample has been
// taken" and this edge's sample (spec 2.4). Nothing here reads a name inside the DUT.
`default_nettype none

module pmu50_port_view #(
    parameter integer SYNC_DEPTH = 2,
    parameter integer CNT_W      = 16,
    parameter integer ADAPTIVE   = 1,
    parameter integer PW         = 5,
    parameter integer PI         = 12,
    parameter integer PS         = 5,
    parameter integer SI_MAX     = 660,
    parameter integer SI_MIN     = 220,
    parameter integer T1         = 220,
    parameter integer T2         = 110,
    parameter integer CTH        = 4,
    parameter integer SMP_ON     = 10
) (
    input  wire                  clk,
    input  wire                  rst_n,
    input  wire                  ig,
    input  wire                  cmp_s,
    input  wire                  cmp_c,
    input  wire                  bus_we,
    input  wire [7:0]            bus_addr,
    input  wire [15:0]           bus_wdata,
    input  wire                  sig,
    input  wire                  smp,
    input  wire                  sr,
    input  wire                  cs,
    input  wire                  cc,
    input  wire [15:0]           si,
    output reg  [SYNC_DEPTH-1:0] sync,
    output reg  [15:0]           tmr,
    output reg                   adaptive,
    output reg  [15:0]           pw, pi, ps, si_max, si_min, t1, t2, smp_on,
    output reg  [7:0]            cth,
    output wire                  kon, koff, upd, first, chg_s, chg_c, skip_clr,
    output reg                   vld,
    output wire                  param_wr, c_legal, c_adaptive,
    output wire [15:0]           c_pw, c_pi, c_ps, c_si_max, c_si_min, c_t1, c_t2, c_smp_on,
    output wire [7:0]            c_cth
);
    // the key through SYNC_DEPTH flops; sync[0] takes ig (spec 2.1)
    always @(posedge clk or negedge rst_n)
        if (!rst_n) sync <= {SYNC_DEPTH{1'b0}};
        else        sync <= {sync, ig};
    wire sig_nxt;
    generate
        if (SYNC_DEPTH == 1) begin : g_nxt1
            assign sig_nxt = ig;
        end else begin : g_nxtn
            assign sig_nxt = sync[SYNC_DEPTH-2];
        end
    endgenerate
    assign kon  = !sig && sig_nxt;
    assign koff = sig && !sig_nxt;

    // register file: what the bus wrote while sig = 1 that passed the legality rules (spec 4)
    wire status_w = bus_we && sig && (bus_addr == 8'h14);
    wire is_param = (bus_addr >= 8'h02) && (bus_addr <= 8'h0B);
    assign c_adaptive = (bus_addr == 8'h02) ? bus_wdata[0]   : adaptive;
    assign c_pw       = (bus_addr == 8'h03) ? bus_wdata      : pw;
    assign c_pi       = (bus_addr == 8'h04) ? bus_wdata      : pi;
    assign c_ps       = (bus_addr == 8'h05) ? bus_wdata      : ps;
    assign c_si_max   = (bus_addr == 8'h06) ? bus_wdata      : si_max;
    assign c_si_min   = (bus_addr == 8'h07) ? bus_wdata      : si_min;
    assign c_t1       = (bus_addr == 8'h08) ? bus_wdata      : t1;
    assign c_t2       = (bus_addr == 8'h09) ? bus_wdata      : t2;
    assign c_cth      = (bus_addr == 8'h0A) ? bus_wdata[7:0] : cth;
    assign c_smp_on   = (bus_addr == 8'h0B) ? bus_wdata      : smp_on;
    wire [17:0] c_wt       = {2'b00, c_pw} + {2'b00, c_pi} + {2'b00, c_ps};
    wire [15:0] c_shortest = c_adaptive ? c_si_min : c_si_max;
    assign c_legal = (c_ps != 0) && (c_si_max != 0) && (c_si_min != 0) && (c_t1 != 0) &&
                     (c_t2 != 0) && (c_smp_on != 0) && (c_cth != 0) && (c_si_min <= c_si_max) &&
                     ((c_pw != 0) || (c_pi != 0)) && (c_wt < {2'b00, c_shortest});
    assign param_wr = bus_we && sig && is_param && c_legal;
    assign skip_clr = status_w && bus_wdata[5];
    always @(posedge clk or negedge rst_n)
        if (!rst_n) begin
            adaptive <= (ADAPTIVE != 0);
            pw <= PW; pi <= PI; ps <= PS; si_max <= SI_MAX; si_min <= SI_MIN;
            t1 <= T1; t2 <= T2; cth <= CTH; smp_on <= SMP_ON;
        end else if (param_wr) begin
            adaptive <= c_adaptive;
            pw <= c_pw; pi <= c_pi; ps <= c_ps; si_max <= c_si_max; si_min <= c_si_min;
            t1 <= c_t1; t2 <= c_t2; cth <= c_cth; smp_on <= c_smp_on;
        end

    // the timer: restarts when sig changes and at the end of each period (spec 2.2)
    wire [16:0] tinc   = {1'b0, tmr} + 17'd1;
    wire [15:0] period = sig ? smp_on : si;
    always @(posedge clk or negedge rst_n)
        if (!rst_n) tmr <= 16'd0;
        else        tmr <= (sig_nxt != sig || tinc >= {1'b0, period}) ? 16'd0 : tinc[15:0];

    // the latches' sample at this edge, the first one, and the changes it shows (spec 2.4)
    always @(posedge clk or negedge rst_n)
        if (!rst_n) vld <= 1'b0;
        else        vld <= vld || upd;
    assign upd   = smp && sr;
    assign first = upd && !vld;
    assign chg_s = upd && vld && (cmp_s != cs);
    assign chg_c = upd && vld && (cmp_c != cc);
endmodule

`default_nettype wire
