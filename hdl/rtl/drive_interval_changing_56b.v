// Drive interval changing unit 56b (spec 2.6).
// [0214]-[0262], FIG. 17 [0263]-[0291], FIG. 18 [0268]-[0279]
//
// Priority: koff > no pulse (hold) > adaptive = 0 > sr = 0 > FIG. 17/18.
// fig17 / fig18 report the path taken at this edge (encodings of spec 2.6).
`default_nettype none

module drive_interval_changing_56b #(
    parameter integer SI_MAX = 660
) (
    input  wire        clk,
    input  wire        rst_n,
    input  wire        koff,
    input  wire        pulse,
    input  wire        sr,
    input  wire        chg_s,
    input  wire        chg_c,
    input  wire        adaptive,
    input  wire [15:0] si_min,
    input  wire [15:0] si_max,
    input  wire [15:0] si_max_nxt,   // register file next state of SI_MAX (loaded at koff)
    input  wire [15:0] t1,
    input  wire [15:0] t2,
    input  wire [7:0]  cth,
    output reg  [15:0] si,
    output reg         hist_s,
    output reg         hist_c,
    output reg  [7:0]  cnt_r,
    output reg  [2:0]  fig17,
    output reg  [2:0]  fig18
);
    localparam [15:0] R_SI = SI_MAX[15:0];

    // FIG. 17 encodings
    localparam [2:0] F17_IDLE = 3'd0, F17_S1_NO_RISE = 3'd1, F17_S5_AT_MIN = 3'd2,
                     F17_S6_SHORTEN = 3'd3, F17_S7_AT_MAX = 3'd4, F17_S9_COUNT = 3'd5,
                     F17_S10_EXPAND = 3'd6, F17_FIXED = 3'd7;
    // FIG. 18 encodings
    localparam [2:0] F18_IDLE = 3'd0, F18_S23_DET_CS = 3'd1, F18_S21_CS_REPEAT = 3'd2,
                     F18_S28_DET_CC = 3'd3, F18_S26_CC_REPEAT = 3'd4, F18_S25_NO_CHANGE = 3'd5;

    // S6: si - T1 saturating at 0, then clamped to the minimum [0260]-[0262].
    wire [16:0] sub      = {1'b0, si} - {1'b0, t1};
`ifdef MUT_SI_SUB_NO_SAT
    // MUTANT: si - T1 does not saturate at 0: T1 > si wraps to a large interval.
    wire [15:0] si_dec   = sub[15:0];
`else
    wire [15:0] si_dec   = sub[16] ? 16'd0 : sub[15:0];
`endif
`ifdef MUT_NO_CLAMP_MIN
    // MUTANT: the clamp of [0262] is missing: si - T1 may go below the minimum.
    wire [15:0] si_short = si_dec;
`else
    wire [15:0] si_short = (si_dec < si_min) ? si_min : si_dec;
`endif
    // S10: si + T2 in 17 bits, clamped to x.
`ifdef MUT_SI_ADD_16BIT
    // MUTANT: si + T2 in 16 bits: a sum past 65535 wraps before the clamp to x.
    wire [16:0] add      = {1'b0, si + t2};
`else
    wire [16:0] add      = {1'b0, si} + {1'b0, t2};
`endif
    wire [15:0] si_long  = (add > {1'b0, si_max}) ? si_max : add[15:0];
    // S9: saturating at 255.
`ifdef MUT_CNT_R_NO_SAT
    // MUTANT: the saturation at 255 is missing: CNTr wraps to 0.
    wire [7:0]  cnt_r_inc = cnt_r + 8'd1;
`else
    wire [7:0]  cnt_r_inc = (cnt_r == 8'hFF) ? 8'hFF : cnt_r + 8'd1;
`endif

`ifdef MUT_CTH_OFF_BY_ONE
    // MUTANT: "CNTr reaches Cth" checked with > instead of >= (one quiet pulse too many).
    wire cth_reached = (cnt_r > cth);
`else
    wire cth_reached = (cnt_r >= cth);
`endif

    reg [15:0] si_n;
    reg        hist_s_n;
    reg        hist_c_n;
    reg [7:0]  cnt_r_n;
    reg        det;

    always @* begin
        si_n     = si;
        hist_s_n = hist_s;
        hist_c_n = hist_c;
        cnt_r_n  = cnt_r;
        fig17    = F17_IDLE;
        fig18    = F18_IDLE;
        det      = 1'b0;
        if (koff) begin
            // Key-off: initial interval x as it stands after this edge (a write of SI_MAX in
            // the same cycle counts), history and CNTr cleared ([0226], [0248]).
`ifdef MUT_KOFF_NO_RELOAD
            // MUTANT: si not reloaded at key-off.
`elsif MUT_KOFF_OLD_X
            // MUTANT: key-off loads x as it was before this edge (a same-cycle SI_MAX write is missed).
            si_n     = si_max;
`else
            si_n     = si_max_nxt;
`endif
            hist_s_n = 1'b0;
            hist_c_n = 1'b0;
            cnt_r_n  = 8'd0;
        end else if (!pulse) begin
            // hold
        end else if (!adaptive) begin
            si_n  = si_max;              // first embodiment: fixed cycle T = x
            fig17 = F17_FIXED;
        end else if (!sr) begin
            fig17 = F17_S1_NO_RISE;      // S1: N
        end else begin
            // ---- FIG. 18: rotation detection
            if (chg_s) begin
                if (hist_s) begin
                    fig18 = F18_S21_CS_REPEAT;       // S21: Y -> S24
                end else begin
                    det      = 1'b1;                 // S22, S23
                    hist_s_n = 1'b1;
                    hist_c_n = 1'b0;
                    fig18    = F18_S23_DET_CS;
                end
`ifdef MUT_CHG_C_IGNORED_WHEN_HIST_S
            // MUTANT: a Cc change is ignored while the Cs history is set.
            end else if (chg_c && !hist_s) begin
`else
            end else if (chg_c) begin
`endif
                if (hist_c) begin
                    fig18 = F18_S26_CC_REPEAT;       // S26: Y -> S24
                end else begin
                    det      = 1'b1;                 // S27, S28
                    hist_c_n = 1'b1;
                    hist_s_n = 1'b0;
                    fig18    = F18_S28_DET_CC;
                end
            end else begin
                fig18 = F18_S25_NO_CHANGE;           // S25: N -> S24
            end
            // ---- FIG. 17: interval changing
            if (det) begin
`ifndef MUT_CNT_R_NO_RESET
                cnt_r_n = 8'd0;                      // S4
`endif
`ifdef MUT_S5_LT
                // MUTANT: S5 "si is the minimum" tested with < (si = min goes to S6).
                if (si < si_min) begin
`else
                if (si <= si_min) begin
`endif
                    fig17 = F17_S5_AT_MIN;           // S5: Y
                end else begin
                    si_n  = si_short;                // S6
                    fig17 = F17_S6_SHORTEN;
                end
`ifdef MUT_S7_GT
            // MUTANT: S7 "si is x" tested with > (at x the quiet pulses go on to S8).
            end else if (si > si_max) begin
`else
            end else if (si >= si_max) begin
`endif
                fig17 = F17_S7_AT_MAX;               // S7: Y
            end else if (cth_reached) begin
                si_n     = si_long;                  // S8: Y, S10
`ifndef MUT_NO_S11
                hist_s_n = 1'b0;                     // S11
                hist_c_n = 1'b0;
`endif
                cnt_r_n  = cnt_r_inc;                // S9
                fig17    = F17_S10_EXPAND;
            end else begin
                cnt_r_n  = cnt_r_inc;                // S8: N, S9
                fig17    = F17_S9_COUNT;
            end
        end
    end

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            si     <= R_SI;
            hist_s <= 1'b0;
            hist_c <= 1'b0;
            cnt_r  <= 8'd0;
        end else begin
            si     <= si_n;
            hist_s <= hist_s_n;
            hist_c <= hist_c_n;
            cnt_r  <= cnt_r_n;
        end
    end
endmodule

`default_nettype wire
