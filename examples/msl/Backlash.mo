within Modelica.Mechanics.Rotational.Examples;
model Backlash "Example to demonstrate backlash (without the ElastoBacklash2 branch)"
  extends Modelica.Icons.Example;
  Components.Fixed fixed1(phi0=0.0);
  Components.SpringDamper springDamper(c=20000.0, d=50.0);
  Components.Inertia inertia1(J=5.0, phi(start=1.570796326794897, fixed=true), w(start=0.0, fixed=true));
  Components.Fixed fixed2(phi0=0.0);
  Components.ElastoBacklash elastoBacklash(c=20000.0, d=50.0, b=0.7853981633974483);
  Components.Inertia inertia2(J=5.0, phi(start=1.570796326794897, fixed=true), w(start=0.0, fixed=true));
  Rotational.Components.Fixed fixed3
    annotation (Placement(transformation(extent={{-50,-50},{-30,-30}})));
  Rotational.Components.ElastoBacklash2 elastoBacklash2(
    c=20E3,
    d=50,
    phi_nominal=1,
    b(displayUnit="deg") = 0.78539816339745)
    annotation (Placement(transformation(extent={{-20,-50},{0,-30}})));
  Rotational.Components.Inertia inertia3(
    J=5,
    w(fixed=true, start=0),
    phi(
      fixed=true,
      start=1.570796326794897,
      displayUnit="deg"))
    annotation (Placement(transformation(extent={{20,-50},{40,-30}})));
equation
  connect(fixed3.flange, elastoBacklash2.flange_a) annotation (Line(points={{-40,-40},{-20,-40}}));
  connect(elastoBacklash2.flange_b, inertia3.flange_a) annotation (Line(points={{0,-40},{20,-40}}));
  connect(fixed1.flange, springDamper.flange_a);
  connect(springDamper.flange_b, inertia1.flange_a);
  connect(fixed2.flange, elastoBacklash.flange_a);
  connect(elastoBacklash.flange_b, inertia2.flange_a);
  annotation(experiment(StopTime=1.0, Interval=0.001, Tolerance=1e-06));
end Backlash;
