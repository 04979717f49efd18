#pragma once

// The parameters of the ten Tusscher-Panfilov 2006 .ode files, shared by the
// per-point model (ten_tusscher_panfilov.cc) and its batched kernel
// (ten_tusscher_panfilov_batch.cc). Internal: not part of the model's
// interface.

namespace systole::Electrophysiology::TenTusscherPanfilovConstants
{
  // Parameters of the .ode (the epicardial file; G_to and G_Ks are the
  // variant's, see the constructor).
  constexpr double P_kna    = 0.03;
  constexpr double g_K1     = 5.405;    // nS/pF
  constexpr double g_Kr     = 0.153;    // nS/pF
  constexpr double g_Na     = 14.838;   // nS/pF
  constexpr double g_bna    = 0.00029;  // nS/pF
  constexpr double g_CaL    = 0.0398;   // l/(F s)
  constexpr double g_bca    = 0.000592; // nS/pF
  constexpr double P_NaK    = 2.724;    // pA/pF
  constexpr double K_mk     = 1.0;      // mM
  constexpr double K_mNa    = 40.0;     // mM
  constexpr double K_NaCa   = 1000.0;   // pA/pF
  constexpr double K_sat    = 0.1;
  constexpr double alpha    = 2.5;
  constexpr double gamma    = 0.35;
  constexpr double Km_Ca    = 1.38;   // mM
  constexpr double Km_Nai   = 87.5;   // mM
  constexpr double g_pCa    = 0.1238; // pA/pF
  constexpr double K_pCa    = 0.0005; // mM
  constexpr double g_pK     = 0.0146; // nS/pF
  constexpr double Ca_o     = 2.0;    // mM
  constexpr double k1_prime = 0.15;   // 1/(mM^2 ms)
  constexpr double k2_prime = 0.045;  // 1/(mM ms)
  constexpr double k3       = 0.06;   // 1/ms
  constexpr double k4       = 0.005;  // 1/ms
  constexpr double EC       = 1.5;    // mM
  constexpr double max_sr   = 2.5;
  constexpr double min_sr   = 1.0;
  constexpr double V_rel    = 0.102;    // 1/ms
  constexpr double V_xfer   = 0.0038;   // 1/ms
  constexpr double K_up     = 0.00025;  // mM
  constexpr double V_leak   = 0.00036;  // 1/ms
  constexpr double Vmax_up  = 0.006375; // mM/ms
  constexpr double Buf_c    = 0.2;      // mM
  constexpr double K_buf_c  = 0.001;    // mM
  constexpr double Buf_sr   = 10.0;     // mM
  constexpr double K_buf_sr = 0.3;      // mM
  constexpr double Buf_ss   = 0.4;      // mM
  constexpr double K_buf_ss = 0.00025;  // mM
  constexpr double V_sr     = 1094.0;   // um^3
  constexpr double V_ss     = 54.68;    // um^3
  constexpr double Na_o     = 140.0;    // mM
  constexpr double R        = 8.314;    // J/(mol K)
  constexpr double T        = 310.0;    // K
  constexpr double F        = 96.485;   // C/mmol
  constexpr double Cm       = 185.0;    // pF
  constexpr double V_c      = 16404.0;  // um^3
  constexpr double K_o      = 5.4;      // mM

  constexpr double RTF = R * T / F; // mV
} // namespace systole::Electrophysiology::TenTusscherPanfilovConstants
