// Count diagnosis (spec 2.7). [0119], [0173]
//
// diag <= |sext(cnt_s_nxt - cnt_c_nxt)| >= 2 | quadrant_skip_nxt, the difference taken modulo
// 2^CNT_W, so diag is aligned with the counters it describes. |d| < 2 <=> d in {-1, 0, +1}.
`default_nettype none

module count_diagnosis #(
    parameter integer CNT_W = 16
) (
    input  wire             clk,
    input  wire             rst_n,
    input  wire [CNT_W-1:0] cnt_s_nxt,
    input  wire [CNT_W-1:0] cnt_c_nxt,
    input  wire             skip_nxt,
    output reg              diag
);
`ifdef MUT_DIAG_NO_WRAP
    // MUTANT: the difference is taken in 16 bits, not modulo 2^CNT_W.
    wire [15:0] d = cnt_s_nxt - cnt_c_nxt;
`else
    wire [CNT_W-1:0] d = cnt_s_nxt - cnt_c_nxt;
`endif
`ifdef MUT_DIAG_UNSIGNED
    // MUTANT: |d| < 2 tested on the unsigned difference (not sign-extended): d = -1 is out of range.
    wire in_range = (d < 2);
`else
    wire in_range = (d == {CNT_W{1'b0}}) || (d == {{(CNT_W-1){1'b0}}, 1'b1}) || (d == {CNT_W{1'b1}});
`endif

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) diag <= 1'b0;
`ifdef MUT_DIAG_NO_SKIP
        // MUTANT: the diagnosis ignores quadrant_skip (a skipped quadrant is not flagged).
        else        diag <= !in_range;
`else
        else        diag <= !in_range || skip_nxt;
`endif
    end
endmodule

`default_nettype wire
