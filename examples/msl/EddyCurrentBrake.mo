within Modelica.Mechanics.Rotational.Examples;
model EddyCurrentBrake "Demonstrate the usage of the rotational eddy current brake"
  extends Modelica.Icons.Example;
  Modelica.Mechanics.Rotational.Sources.EddyCurrentTorque eddyCurrentTorque(
    useTau_nominalInput=true,
    tau_nominal=100,
    w_nominal=10,
    useSupport=false,
    alpha20(displayUnit="1/K") = Modelica.Electrical.Machines.Thermal.Constants.alpha20Copper,
    TRef=293.15,
    useHeatPort=true)
    annotation (Placement(transformation(extent={{-10,-10},{10,10}})));
  Modelica.Mechanics.Rotational.Components.Inertia inertia(
    phi(fixed=true, start=0),
    J=1,
    w(fixed=true, start=20));
  Modelica.Thermal.HeatTransfer.Components.HeatCapacitor heatCapacitor(C=1, T(
        fixed=true)) annotation (Placement(transformation(
        extent={{-10,-10},{10,10}},
        rotation=180,
        origin={-10,-30})));
  Blocks.Sources.Ramp ramp(
    height=100,
    duration=0.1,
    offset=0,
    startTime=0.1);
equation
  connect(eddyCurrentTorque.flange, inertia.flange_a);
  connect(eddyCurrentTorque.heatPort, heatCapacitor.port);
  connect(ramp.y, eddyCurrentTorque.tau_input);
  annotation (
    experiment(StopTime=1.0, Interval=0.001),
    Documentation(info="<html>
<p>stiction's test model of MSL's EddyCurrentBrake example, in MSL's own style.</p>
</html>"));
end EddyCurrentBrake;
