within Modelica.Mechanics.Rotational.Examples;
model EddyCurrentBrake "Demonstrate the usage of the rotational eddy current brake (MSL 4.0, as MAP-LIB's reference ran it)"
  extends Modelica.Icons.Example;
  Sources.EddyCurrentTorque eddyCurrentTorque(tau_nominal=100.0, w_nominal=10.0, useSupport=false, alpha20=0.00392, TRef=293.15, useHeatPort=true);
  Components.Inertia inertia(J=1.0, phi(start=0.0, fixed=true), w(start=20.0, fixed=true));
  Modelica.Thermal.HeatTransfer.Components.HeatCapacitor heatCapacitor(C=1.0, T(start=293.15, fixed=true));
equation
  connect(eddyCurrentTorque.flange, inertia.flange_a);
  connect(eddyCurrentTorque.heatPort, heatCapacitor.port);
  annotation(experiment(StopTime=1.0, Interval=0.0005, Tolerance=1e-06));
end EddyCurrentBrake;
