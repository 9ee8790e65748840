// pmu_regbank: the microprocessor's register map of the PMU 50 core.
//
// Spec 2.8. At key-on the MPU reads CNTs/CNTc ([0108], [0163]); Pw, Pi, Ps are programmable
// ([0321]-[0323]); T1, T2, x, the minimum and Cth are set per device ([0259]); the on-key
// sampling period is programmable ([0349]). The MPU is powered only while the key is on
// ([0205], interpretation I15), so any write with Sig = 0 is refused.
//
// All parameter registers live in one packed register cfg_q (pmu50_alt_pkg::cfg_t). A write
// builds the candidate set with the one field replaced (only the field's width of the data is
// taken) and is accepted only when the candidate is legal (spec 4); a refused write leaves every
// register unchanged and sets the sticky bus_err_q.

module pmu_regbank import pmu50_alt_pkg::*; #(
  parameter int unsigned SYNC_DEPTH = 2,
  parameter int unsigned CNT_W      = 16,
  parameter cfg_t        CFG_RESET  = CFG_DEFAULT
) (
  input  logic              clk,
  input  logic              rst_n,
  // bus
  input  logic              bus_we_i,
  input  logic [BusAw-1:0]  bus_addr_i,
  input  logic [BusDw-1:0]  bus_wdata_i,
  output logic [BusDw-1:0]  rdata_o,
  output logic              bus_err_o,
  // key state: writes only with Sig = 1
  input  logic              key_on_i,
  // read-only state of the other blocks (values before the edge)
  input  logic [CNT_W-1:0]  cnt_s_i,
  input  logic [CNT_W-1:0]  cnt_c_i,
  input  logic [7:0]        cnt_r_i,
  input  logic [15:0]       interval_i,
  input  logic              sign_s_i,
  input  logic              sign_c_i,
  input  logic              hist_s_i,
  input  logic              hist_c_i,
  input  logic              diag_i,
  input  logic              qskip_i,
  input  logic              vld_i,
  input  logic              sr_i,
  // parameters in force this cycle, and x as it stands after this edge
  output cfg_t              cfg_o,
  output logic [15:0]       si_max_next_o,
  // STATUS.quadrant_skip write-1-to-clear strobe (comb)
  output logic              qskip_clr_o
);

  cfg_t              cfg_q, cfg_d, cfg_cand;
  logic              cand_is_param;
  logic              status_wr, param_wr, refused;
  logic              bus_err_q, bus_err_d;
  logic [BusDw-1:0]  rdata_q, rdata_d;
  logic [BusDw-1:0]  status_word;

  // -------------------------------------------------------------------------------------------
  // Write path
  // -------------------------------------------------------------------------------------------
  always_comb begin
    cfg_cand      = cfg_q;
    cand_is_param = 1'b1;
    case (bus_addr_i)
      ADDR_CTRL:   cfg_cand.adaptive = bus_wdata_i[0];     // a write of 0x0002 is adaptive = 0
      ADDR_PW:     cfg_cand.pw       = bus_wdata_i;
      ADDR_PI:     cfg_cand.pi       = bus_wdata_i;
      ADDR_PS:     cfg_cand.ps       = bus_wdata_i;
      ADDR_SI_MAX: cfg_cand.si_max   = bus_wdata_i;
      ADDR_SI_MIN: cfg_cand.si_min   = bus_wdata_i;
      ADDR_T1:     cfg_cand.t1       = bus_wdata_i;
      ADDR_T2:     cfg_cand.t2       = bus_wdata_i;
      ADDR_CTH:    cfg_cand.cth      = bus_wdata_i[7:0];   // a write of 0x0100 is Cth = 0
      ADDR_SMP_ON: cfg_cand.smp_on   = bus_wdata_i;
      default:     cand_is_param     = 1'b0;
    endcase
  end

  assign status_wr = bus_we_i & key_on_i & (bus_addr_i == ADDR_STATUS);
  assign param_wr  = bus_we_i & key_on_i & cand_is_param & cfg_is_legal(cfg_cand);
  // Key off, read-only or unmapped address, illegal value: refused.
  assign refused   = bus_we_i & ~(status_wr | param_wr);

  always_comb begin
    cfg_d = cfg_q;
    if (param_wr) begin
      cfg_d = cfg_cand;
    end
  end

  // W1C of STATUS: bit 5 clears quadrant_skip (in the counter block), bit 9 clears bus_err.
  // A refusal in the same cycle wins over the clear.
  assign qskip_clr_o = status_wr & bus_wdata_i[STATUS_QSKIP];
  assign bus_err_d   = refused | (bus_err_q & ~(status_wr & bus_wdata_i[STATUS_BUS_ERR]));

  // -------------------------------------------------------------------------------------------
  // Read path: registered, one cycle latency; the mux sees the registers before the edge.
  // -------------------------------------------------------------------------------------------
  always_comb begin
    status_word                 = '0;
    status_word[STATUS_CS]      = sign_s_i;
    status_word[STATUS_CC]      = sign_c_i;
    status_word[STATUS_HIST_S]  = hist_s_i;
    status_word[STATUS_HIST_C]  = hist_c_i;
    status_word[STATUS_DIAG]    = diag_i;
    status_word[STATUS_QSKIP]   = qskip_i;
    status_word[STATUS_SIG]     = key_on_i;
    status_word[STATUS_VLD]     = vld_i;
    status_word[STATUS_SR]      = sr_i;
    status_word[STATUS_BUS_ERR] = bus_err_q;
  end

  always_comb begin
    rdata_d = '0;  // unmapped addresses read 0
    case (bus_addr_i)
      ADDR_ID:      rdata_d = ID_VALUE;
      ADDR_VERSION: rdata_d = VERSION_VALUE;
      ADDR_CTRL:    rdata_d = {15'd0, cfg_q.adaptive};
      ADDR_PW:      rdata_d = cfg_q.pw;
      ADDR_PI:      rdata_d = cfg_q.pi;
      ADDR_PS:      rdata_d = cfg_q.ps;
      ADDR_SI_MAX:  rdata_d = cfg_q.si_max;
      ADDR_SI_MIN:  rdata_d = cfg_q.si_min;
      ADDR_T1:      rdata_d = cfg_q.t1;
      ADDR_T2:      rdata_d = cfg_q.t2;
      ADDR_CTH:     rdata_d = {8'd0, cfg_q.cth};
      ADDR_SMP_ON:  rdata_d = cfg_q.smp_on;
      ADDR_CFG:     rdata_d = {3'd0, 5'(CNT_W), 5'd0, 3'(SYNC_DEPTH)};
      ADDR_CNT_S:   rdata_d = 16'(signed'(cnt_s_i));   // sign-extended from CNT_W
      ADDR_CNT_C:   rdata_d = 16'(signed'(cnt_c_i));
      ADDR_CNT_R:   rdata_d = {8'd0, cnt_r_i};
      ADDR_SI:      rdata_d = interval_i;
      ADDR_STATUS:  rdata_d = status_word;
      default:      rdata_d = '0;
    endcase
  end

  // -------------------------------------------------------------------------------------------
  // Registers
  // -------------------------------------------------------------------------------------------
  always_ff @(posedge clk or negedge rst_n) begin
    if (!rst_n) begin
      cfg_q     <= CFG_RESET;
      bus_err_q <= 1'b0;
      rdata_q   <= '0;
    end else begin
      cfg_q     <= cfg_d;
      bus_err_q <= bus_err_d;
      rdata_q   <= rdata_d;
    end
  end

  assign cfg_o         = cfg_q;
  assign si_max_next_o = cfg_d.si_max;
  assign rdata_o       = rdata_q;
  assign bus_err_o     = bus_err_q;

endmodule : pmu_regbank
