// Up/down counters 58c (sine) / 58d (cosine) (spec 2.5).
// [0094]-[0100], [0211], [0355]
//
// Compact form of the rules [0096]-[0099]: when only Cs changes, cnt_s += (cs_new == cc) ? +1 : -1;
// when only Cc changes, cnt_c += (cc_new != cs) ? +1 : -1. Both change: counters hold and the
// sticky quadrant_skip is set (set wins over the W1C clear). The first sample after reset presets
// the counters from the sampled quadrant. CNT_W-bit two's complement, wrapping.
`default_nettype none

module updown_counter_58cd #(
    parameter integer CNT_W = 16
) (
    input  wire             clk,
    input  wire             rst_n,
    input  wire             upd,
    input  wire             first,
    input  wire             cs,
    input  wire             cc,
    input  wire             cs_new,
    input  wire             cc_new,
    input  wire             skip_clr,
    output reg  [CNT_W-1:0] cnt_s,
    output reg  [CNT_W-1:0] cnt_c,
    output reg              quadrant_skip,
    // next values, for the count diagnosis
    output reg  [CNT_W-1:0] cnt_s_nxt,
    output reg  [CNT_W-1:0] cnt_c_nxt,
    output wire             skip_nxt
);
    localparam [CNT_W-1:0] ONE = {{(CNT_W-1){1'b0}}, 1'b1};
    localparam [CNT_W-1:0] TWO = {{(CNT_W-2){1'b0}}, 2'b10};
    localparam [CNT_W-1:0] ZERO = {CNT_W{1'b0}};

    wire chg_s = upd && !first && (cs != cs_new);
    wire chg_c = upd && !first && (cc != cc_new);
    wire both  = chg_s && chg_c;

    // Direction of a single sign change ([0096]-[0099]).
`ifdef MUT_CNT_C_SIGN
    // MUTANT: [0099] with the wrong sign: Cc 1->0 while Cs = 1 counts down (and 0->1 up).
    wire up_s = (cs_new == cc);
    wire up_c = cs ? cc_new : (cc_new != cs);
`else
    wire up_s = (cs_new == cc);
    wire up_c = (cc_new != cs);
`endif

    always @* begin
        cnt_s_nxt = cnt_s;
        cnt_c_nxt = cnt_c;
        if (first) begin
            // preset: (cs,cc) = (1,1) -> (0,0); (1,0) -> (0,1); (0,0) -> (1,1); (0,1) -> (1,2)
            case ({cs_new, cc_new})
                2'b11:   begin cnt_s_nxt = ZERO; cnt_c_nxt = ZERO; end
                2'b10:   begin cnt_s_nxt = ZERO; cnt_c_nxt = ONE;  end
                2'b00:   begin cnt_s_nxt = ONE;  cnt_c_nxt = ONE;  end
`ifdef MUT_PRESET_Q3
                // MUTANT: quadrant 3 preset like quadrant 2.
                default: begin cnt_s_nxt = ONE;  cnt_c_nxt = ONE;  end
`else
                default: begin cnt_s_nxt = ONE;  cnt_c_nxt = TWO;  end
`endif
            endcase
`ifdef MUT_BOTH_COUNTS_S
        // MUTANT: "both changed" left out of the sine counter's condition: CNTs counts at a skip.
        end else if (chg_s) begin
`else
        end else if (chg_s && !both) begin
`endif
            cnt_s_nxt = up_s ? cnt_s + ONE : cnt_s - ONE;
        end else if (chg_c && !both) begin
`ifdef MUT_CNT_C_SAT_MAX
            // MUTANT: CNTc stops at its largest positive value instead of wrapping.
            cnt_c_nxt = up_c ? ((cnt_c == {1'b0, {(CNT_W-1){1'b1}}}) ? cnt_c : cnt_c + ONE) : cnt_c - ONE;
`else
            cnt_c_nxt = up_c ? cnt_c + ONE : cnt_c - ONE;
`endif
        end
    end

    // Set wins over clear: a skip seen in the same cycle as the MPU's clear is not lost.
`ifdef MUT_SKIP_CLR_WINS
    // MUTANT: the W1C clear wins over a skip seen on the same edge (the skip is lost).
    assign skip_nxt = (both || quadrant_skip) && !skip_clr;
`else
    assign skip_nxt = both || (quadrant_skip && !skip_clr);
`endif

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            cnt_s         <= ZERO;
            cnt_c         <= ZERO;
            quadrant_skip <= 1'b0;
        end else begin
            cnt_s         <= cnt_s_nxt;
            cnt_c         <= cnt_c_nxt;
            quadrant_skip <= skip_nxt;
        end
    end
endmodule

`default_nettype wire
