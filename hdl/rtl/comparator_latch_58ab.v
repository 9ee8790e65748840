// Comparator latches 58a / 58b (spec 2.4).
// [0086]-[0087], [0211], [0349], [0354]
//
// Cs / Cc take the raw comparator decisions at a sampling strobe while Sr = 1 and hold
// otherwise (the latch is on Vp, [0211]). vld marks that a first sample has been taken.
`default_nettype none

module comparator_latch_58ab (
    input  wire clk,
    input  wire rst_n,
    input  wire cmp_s,
    input  wire cmp_c,
    input  wire smp,
    input  wire sr,
    output reg  cs,
    output reg  cc,
    output reg  vld,
    output wire upd,
    output wire first,
    output wire cs_new,
    output wire cc_new,
    output wire chg_s,
    output wire chg_c
);
`ifdef MUT_LATCH_NO_SR
    // MUTANT: the latch takes a sample at every strobe, Sr not checked.
    assign upd    = smp;
`else
    assign upd    = smp && sr;
`endif
    assign first  = upd && !vld;
    assign cs_new = upd ? cmp_s : cs;
    assign cc_new = upd ? cmp_c : cc;
`ifdef MUT_CHG_NO_VLD
    // MUTANT: a Cs change is flagged at the first sample too (vld not checked).
    assign chg_s  = upd && (cs_new != cs);
`else
    assign chg_s  = upd && vld && (cs_new != cs);
`endif
    assign chg_c  = upd && vld && (cc_new != cc);

    always @(posedge clk or negedge rst_n) begin
        if (!rst_n) begin
            cs  <= 1'b0;
            cc  <= 1'b0;
            vld <= 1'b0;
        end else begin
            cs  <= cs_new;
            cc  <= cc_new;
`ifdef MUT_VLD_ON_SMP
            // MUTANT: vld set by the strobe even when Sr = 0 (no sample taken).
            vld <= vld || smp;
`else
            vld <= vld || upd;
`endif
        end
    end
endmodule

`default_nettype wire
